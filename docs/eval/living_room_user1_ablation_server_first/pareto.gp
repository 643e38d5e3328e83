set terminal svg size 720,440 dynamic enhanced font 'sans,12' background '#ffffff'
set output 'docs/eval/living_room_user1_ablation_server_first/pareto.svg'
set title 'run time vs error' noenhanced
set xlabel 'client + server ms per frame (both eyes)' noenhanced
set ylabel 'bit error' noenhanced
set key outside right top noenhanced
set grid
plot 'docs/eval/living_room_user1_ablation_server_first/pareto.dat' index 0 using 1:2 with points pt 1 title 'full-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/pareto.dat' index 1 using 1:2 with points pt 2 title 'full-no-bilinear-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/pareto.dat' index 2 using 1:2 with points pt 3 title 'full-no-depth-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/pareto.dat' index 3 using 1:2 with points pt 4 title 'full-no-other-eye-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/pareto.dat' index 4 using 1:2 with points pt 5 title 'full-no-shadow-fill-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/pareto.dat' index 5 using 1:2 with points pt 6 title 'full-no-shadow-edges-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/pareto.dat' index 6 using 1:2 with points pt 7 title 'full-no-shadow-first-no-older', 'docs/eval/living_room_user1_ablation_server_first/pareto.dat' index 7 using 1:2 with points pt 1 title 'full-no-shadow-first-no-neighbour', 'docs/eval/living_room_user1_ablation_server_first/pareto.dat' index 8 using 1:2 with points pt 2 title 'Pareto front'
