set terminal svg size 720,440 dynamic enhanced font 'sans,12' background '#ffffff'
set output 'docs/eval/living_room_user1_xmax/flip_vs_frames.svg'
set title 'FLIP (LDR) of the shaded image' noenhanced
set xlabel 'frames predicted (x = min(x_max, p))' noenhanced
set ylabel 'mean FLIP (0 = identical)' noenhanced
set key outside right top noenhanced
set grid
plot 'docs/eval/living_room_user1_xmax/flip_vs_frames.dat' index 0 using 1:2 with linespoints pt 1 title 'paper rtt 100 ms'
