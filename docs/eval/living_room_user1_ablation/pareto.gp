set terminal svg size 720,440 dynamic enhanced font 'sans,12' background '#ffffff'
set output 'docs/eval/living_room_user1_ablation/pareto.svg'
set title 'run time vs error' noenhanced
set xlabel 'client + server ms per frame (both eyes)' noenhanced
set ylabel 'bit error' noenhanced
set key outside right top noenhanced
set grid
plot 'docs/eval/living_room_user1_ablation/pareto.dat' index 0 using 1:2 with points pt 1 title 'paper+pred', 'docs/eval/living_room_user1_ablation/pareto.dat' index 1 using 1:2 with points pt 2 title 'local', 'docs/eval/living_room_user1_ablation/pareto.dat' index 2 using 1:2 with points pt 3 title 'full', 'docs/eval/living_room_user1_ablation/pareto.dat' index 3 using 1:2 with points pt 4 title 'full-no-bilinear', 'docs/eval/living_room_user1_ablation/pareto.dat' index 4 using 1:2 with points pt 5 title 'full-no-depth', 'docs/eval/living_room_user1_ablation/pareto.dat' index 5 using 1:2 with points pt 6 title 'full-no-other-eye', 'docs/eval/living_room_user1_ablation/pareto.dat' index 6 using 1:2 with points pt 7 title 'full-no-shadow-fill', 'docs/eval/living_room_user1_ablation/pareto.dat' index 7 using 1:2 with points pt 1 title 'full-no-shadow-edges', 'docs/eval/living_room_user1_ablation/pareto.dat' index 8 using 1:2 with points pt 2 title 'full-no-shadow-first', 'docs/eval/living_room_user1_ablation/pareto.dat' index 9 using 1:2 with points pt 3 title 'full-no-pred', 'docs/eval/living_room_user1_ablation/pareto.dat' index 10 using 1:2 with points pt 4 title 'Pareto front'
