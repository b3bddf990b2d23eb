# Work-precision diagram of scene sdnd100-d, written by csim compare.
# Run `gnuplot work_precision.gp` in this folder. The data are the rows of work_precision.csv that
# succeeded with a non-zero max_rel_error (log axes): median wall time (s), max_rel_error, label.
$moreau_jean << EOD
0.000959262 0.52774634 "h=0.001"
0.00626708 0.0046369222 "h=0.0001"
0.054633033 7.8589685e-05 "h=1e-05"
0.52008881 5.913666e-07 "h=1e-06"
EOD
$ida << EOD
0.013274502 17.69463 "tol=0.01"
0.015677423 0.16826891 "tol=0.0001"
0.01539326 0.45026071 "tol=1e-06"
0.015619507 0.049244436 "tol=1e-08"
0.018063853 0.05054641 "tol=1e-10"
EOD
$ida_events << EOD
0.067106558 2.8982068e-08 "tol=0.01"
0.068931041 3.2822327e-08 "tol=0.0001"
0.067549679 3.1222219e-08 "tol=1e-06"
0.068443299 4.732997e-08 "tol=1e-08"
0.067804548 3.762265e-08 "tol=1e-10"
EOD
if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1000,700 font ",11"
} else {
  set terminal png size 1000,700
}
set output "work_precision.png"
set title "sdnd100-d: work-precision (max relative error of the analytical checks)"
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
     $ida using 1:2 with linespoints linecolor 2 pointtype 7 title "ida", \
     $ida using 1:2:3 with labels offset char 1,0.6 left textcolor lt 2 notitle, \
     $ida_events using 1:2 with linespoints linecolor 3 pointtype 7 title "ida-events", \
     $ida_events using 1:2:3 with labels offset char 1,0.6 left textcolor lt 3 notitle
