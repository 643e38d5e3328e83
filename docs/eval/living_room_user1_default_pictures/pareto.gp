set terminal svg size 720,440 dynamic enhanced font 'sans,12' background '#ffffff'
set output 'docs/eval/living_room_user1_default_pictures/pareto.svg'
set title 'run time vs error' noenhanced
set xlabel 'client + server ms per frame (both eyes)' noenhanced
set ylabel 'bit error' noenhanced
set key outside right top noenhanced
set grid
plot 'docs/eval/living_room_user1_default_pictures/pareto.dat' index 0 using 1:2 with points pt 1 title 'default', 'docs/eval/living_room_user1_default_pictures/pareto.dat' index 1 using 1:2 with points pt 2 title 'local', 'docs/eval/living_room_user1_default_pictures/pareto.dat' index 2 using 1:2 with points pt 3 title 'paper+pred', 'docs/eval/living_room_user1_default_pictures/pareto.dat' index 3 using 1:2 with points pt 4 title 'Pareto front'
