set terminal svg size 720,440 dynamic enhanced font 'sans,12' background '#ffffff'
set output 'docs/eval/living_room_user1_default_pictures/response_vs_ping.svg'
set title 'pose sent -> visibility in use' noenhanced
set xlabel 'round trip (ms)' noenhanced
set ylabel 'response (ms)' noenhanced
set key outside right top noenhanced
set grid
plot 'docs/eval/living_room_user1_default_pictures/response_vs_ping.dat' index 0 using 1:2 with linespoints pt 1 title 'default', 'docs/eval/living_room_user1_default_pictures/response_vs_ping.dat' index 1 using 1:2 with linespoints pt 2 title 'local', 'docs/eval/living_room_user1_default_pictures/response_vs_ping.dat' index 2 using 1:2 with linespoints pt 3 title 'paper+pred'
