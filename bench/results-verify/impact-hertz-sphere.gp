set terminal pngcairo size 1100,450 font ',10'
set output 'bench/results-verify/impact-hertz-sphere.png'
set logscale xy
set grid
set key bottom left
set format y '%.0e'
set multiplot layout 1,2 title 'impact-hertz-sphere: error against run time and dt'
set xlabel 'wall time of the simulation loop (s)'
set ylabel 'relative error'
plot 'bench/results-verify/impact-hertz-sphere.dat' index 0 using 2:3 with linespoints pt 7 title '2D synchronized', 'bench/results-verify/impact-hertz-sphere.dat' index 1 using 2:3 with linespoints pt 7 title '2D verlet', 'bench/results-verify/impact-hertz-sphere.dat' index 2 using 2:3 with linespoints pt 7 title '2D synchronized-notouch', 'bench/results-verify/impact-hertz-sphere.dat' index 3 using 2:3 with linespoints pt 7 title '2D verlet-notouch', 'bench/results-verify/impact-hertz-sphere.dat' index 4 using 2:3 with linespoints pt 7 title '3D synchronized', 'bench/results-verify/impact-hertz-sphere.dat' index 5 using 2:3 with linespoints pt 7 title '3D verlet', 'bench/results-verify/impact-hertz-sphere.dat' index 6 using 2:3 with linespoints pt 7 title '3D synchronized-notouch', 'bench/results-verify/impact-hertz-sphere.dat' index 7 using 2:3 with linespoints pt 7 title '3D verlet-notouch'
set xlabel 'time step dt (s)'
plot 'bench/results-verify/impact-hertz-sphere.dat' index 0 using 1:3 with linespoints pt 7 title '2D synchronized (order 2.02)', 'bench/results-verify/impact-hertz-sphere.dat' index 1 using 1:3 with linespoints pt 7 title '2D verlet (order 1)', 'bench/results-verify/impact-hertz-sphere.dat' index 2 using 1:3 with linespoints pt 7 title '2D synchronized-notouch (order 1.23)', 'bench/results-verify/impact-hertz-sphere.dat' index 3 using 1:3 with linespoints pt 7 title '2D verlet-notouch (order 1.1)', 'bench/results-verify/impact-hertz-sphere.dat' index 4 using 1:3 with linespoints pt 7 title '3D synchronized (order 2.02)', 'bench/results-verify/impact-hertz-sphere.dat' index 5 using 1:3 with linespoints pt 7 title '3D verlet (order 1)', 'bench/results-verify/impact-hertz-sphere.dat' index 6 using 1:3 with linespoints pt 7 title '3D synchronized-notouch (order 1.23)', 'bench/results-verify/impact-hertz-sphere.dat' index 7 using 1:3 with linespoints pt 7 title '3D verlet-notouch (order 1.1)'
unset multiplot
