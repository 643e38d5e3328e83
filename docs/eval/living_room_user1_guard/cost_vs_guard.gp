set terminal svg size 720,440 dynamic enhanced font 'sans,12' background '#ffffff'
set output 'docs/eval/living_room_user1_guard/cost_vs_guard.svg'
set title 'server trace time vs guard band' noenhanced
set xlabel 'guard band, extra pixels per row at this eye size' noenhanced
set ylabel 'ms per eye' noenhanced
set key outside right top noenhanced
set grid
plot 'docs/eval/living_room_user1_guard/cost_vs_guard.dat' index 0 using 1:2 with linespoints pt 1 title 'server (trace, per eye)'
