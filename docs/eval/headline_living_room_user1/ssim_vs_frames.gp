set terminal svg size 720,440 dynamic enhanced font 'sans,12' background '#ffffff'
set output 'docs/eval/headline_living_room_user1/ssim_vs_frames.svg'
set title 'SSIM of the shaded luma' noenhanced
set xlabel 'frames predicted (p: age of the visibility, x_max unlimited)' noenhanced
set ylabel 'SSIM' noenhanced
set key outside right top noenhanced
set grid
plot 'docs/eval/headline_living_room_user1/ssim_vs_frames.dat' index 0 using 1:2 with linespoints pt 1 title 'paper+pred', 'docs/eval/headline_living_room_user1/ssim_vs_frames.dat' index 1 using 1:2 with linespoints pt 2 title 'local', 'docs/eval/headline_living_room_user1/ssim_vs_frames.dat' index 2 using 1:2 with linespoints pt 3 title 'full'
