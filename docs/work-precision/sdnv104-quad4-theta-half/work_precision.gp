# Work-precision diagram of scene sdnv104-quad4, written by csim compare.
# Run `gnuplot work_precision.gp` in this folder. The data are the rows of work_precision.csv that
# succeeded with a non-zero max_rel_error (log axes): median wall time (s), max_rel_error, label.
$moreau_jean << EOD
0.005255395 3.0989654e-05 "h=0.01"
0.038632431 3.228448e-07 "h=0.001"
0.24824978 3.2540693 "h=0.0001"
EOD
if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1000,700 font ",11"
} else {
  set terminal png size 1000,700
}
set output "work_precision.png"
set title "sdnv104-quad4: work-precision (max relative error of the analytical checks)"
set xlabel "median wall time of the time loop (s)"
set ylabel "max relative error"
set logscale xy
set format x "%g"
set format y "%.0e"
set grid
set key top right
set offsets graph 0.05, graph 0.15, graph 0.1, graph 0.1
plot $moreau_jean using 1:2 with linespoints linecolor 1 pointtype 7 title "moreau-jean", \
     $moreau_jean using 1:2:3 with labels offset char 1,0.6 left textcolor lt 1 notitle
