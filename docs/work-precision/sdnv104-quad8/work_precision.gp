# Work-precision diagram of scene sdnv104-quad8, written by csim compare.
# Run `gnuplot work_precision.gp` in this folder. The data are the rows of work_precision.csv that
# succeeded with a non-zero max_rel_error (log axes): median wall time (s), max_rel_error, label.
$moreau_jean << EOD
0.017879466 0.0022100277 "h=0.01"
0.096838404 0.00021846643 "h=0.001"
0.7207086 2.2305003e-05 "h=0.0001"
EOD
$generalized_alpha << EOD
0.00976178 0.00012353215 "h=0.01"
0.081636025 1.0747429e-06 "h=0.001"
0.6882553 4.7045073e-07 "h=0.0001"
EOD
$ida << EOD
7.2512864 0.00062550511 "tol=0.0001"
23.064656 1.5759859e-05 "tol=1e-06"
EOD
if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1000,700 font ",11"
} else {
  set terminal png size 1000,700
}
set output "work_precision.png"
set title "sdnv104-quad8: work-precision (max relative error of the analytical checks)"
set xlabel "median wall time of the time loop (s)"
set ylabel "max relative error"
set logscale xy
set format x "%g"
set format y "%.0e"
set grid
set key top right
set offsets graph 0.05, graph 0.15, graph 0.1, graph 0.1
plot $moreau_jean using 1:2 with linespoints linecolor 1 pointtype 7 title "moreau-jean", \
     $moreau_jean using 1:2:3 with labels offset char 1,0.6 left textcolor lt 1 notitle, \
     $generalized_alpha using 1:2 with linespoints linecolor 2 pointtype 7 title "generalized-alpha", \
     $generalized_alpha using 1:2:3 with labels offset char 1,0.6 left textcolor lt 2 notitle, \
     $ida using 1:2 with linespoints linecolor 3 pointtype 7 title "ida", \
     $ida using 1:2:3 with labels offset char 1,0.6 left textcolor lt 3 notitle
