set terminal svg size 720,440 dynamic enhanced font 'sans,12' background '#ffffff'
set output 'docs/eval/living_room_user1_default_pictures/psnr_vs_frames.svg'
set title 'PSNR of the shaded luma' noenhanced
set xlabel 'frames predicted (p: age of the visibility, x_max unlimited)' noenhanced
set ylabel 'PSNR (dB)' noenhanced
set key outside right top noenhanced
set grid
plot 'docs/eval/living_room_user1_default_pictures/psnr_vs_frames.dat' index 0 using 1:2 with linespoints pt 1 title 'default', 'docs/eval/living_room_user1_default_pictures/psnr_vs_frames.dat' index 1 using 1:2 with linespoints pt 2 title 'local', 'docs/eval/living_room_user1_default_pictures/psnr_vs_frames.dat' index 2 using 1:2 with linespoints pt 3 title 'paper+pred'
