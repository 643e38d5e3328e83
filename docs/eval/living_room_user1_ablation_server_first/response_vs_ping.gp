set terminal svg size 720,440 dynamic enhanced font 'sans,12' background '#ffffff'
set output 'docs/eval/living_room_user1_ablation_server_first/response_vs_ping.svg'
set title 'pose sent -> visibility in use' noenhanced
set xlabel 'round trip (ms)' noenhanced
set ylabel 'response (ms)' noenhanced
set key outside right top noenhanced
set grid
plot 'docs/eval/living_room_user1_ablation_server_first/response_vs_ping.dat' index 0 using 1:2 with linespoints pt 1 title 'full-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/response_vs_ping.dat' index 1 using 1:2 with linespoints pt 2 title 'full-no-bilinear-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/response_vs_ping.dat' index 2 using 1:2 with linespoints pt 3 title 'full-no-depth-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/response_vs_ping.dat' index 3 using 1:2 with linespoints pt 4 title 'full-no-other-eye-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/response_vs_ping.dat' index 4 using 1:2 with linespoints pt 5 title 'full-no-shadow-fill-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/response_vs_ping.dat' index 5 using 1:2 with linespoints pt 6 title 'full-no-shadow-edges-no-shadow-first', 'docs/eval/living_room_user1_ablation_server_first/response_vs_ping.dat' index 6 using 1:2 with linespoints pt 7 title 'full-no-shadow-first-no-older', 'docs/eval/living_room_user1_ablation_server_first/response_vs_ping.dat' index 7 using 1:2 with linespoints pt 1 title 'full-no-shadow-first-no-neighbour'
