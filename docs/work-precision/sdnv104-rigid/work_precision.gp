# Work-precision diagram of scene sdnv104-rigid, written by csim compare.
# Run `gnuplot work_precision.gp` in this folder. The data are the rows of work_precision.csv that
# succeeded with a non-zero max_rel_error (log axes): median wall time (s), max_rel_error, label.
$moreau_jean << EOD
0.000333255 0.013760056 "h=0.1"
0.002945778 0.0022703788 "h=0.01"
0.013643676 0.00022298218 "h=0.001"
0.12500671 1.5682213e-05 "h=0.0001"
1.293016 1.2098353e-06 "h=1e-05"
EOD
$generalized_alpha << EOD
0.000333245 0.019653951 "h=0.1"
0.003096031 0.0025615433 "h=0.01"
0.01453475 0.0002230052 "h=0.001"
0.14638995 1.5682228e-05 "h=0.0001"
1.3674607 1.2098353e-06 "h=1e-05"
EOD
$ida << EOD
0.097497419 0.063101049 "tol=0.01"
0.14809412 0.012840639 "tol=0.0001"
0.13391869 0.00028000199 "tol=1e-06"
0.017557993 5.2509846e-05 "tol=1e-08"
0.02169502 5.3505106e-05 "tol=1e-10"
EOD
$ida_events << EOD
0.072718907 2.8041519e-09 "tol=0.01"
0.068882445 2.8041672e-09 "tol=0.0001"
0.072834167 3.0098014e-09 "tol=1e-06"
0.068880011 1.7188385e-09 "tol=1e-08"
0.070903058 3.54e-11 "tol=1e-10"
EOD
if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1000,700 font ",11"
} else {
  set terminal png size 1000,700
}
set output "work_precision.png"
set title "sdnv104-rigid: work-precision (max relative error of the analytical checks)"
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
     $ida using 1:2:3 with labels offset char 1,0.6 left textcolor lt 3 notitle, \
     $ida_events using 1:2 with linespoints linecolor 4 pointtype 7 title "ida-events", \
     $ida_events using 1:2:3 with labels offset char 1,0.6 left textcolor lt 4 notitle
