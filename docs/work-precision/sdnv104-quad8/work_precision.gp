# Work-precision diagram of scene sdnv104-quad8, written by csim compare.
# Run `gnuplot work_precision.gp` in this folder. The data are the rows of work_precision.csv that
# succeeded with a non-zero max_rel_error (log axes): median wall time (s), max_rel_error, label.
$moreau_jean << EOD
0.023906237 0.0022100297 "h=0.01"
0.22357123 0.00021845497 "h=0.001"
1.876587 2.2310083e-05 "h=0.0001"
EOD
$generalized_alpha << EOD
0.044037974 4.0589625e-05 "h=0.01"
0.42516958 3.62153e-07 "h=0.001"
3.5855267 3.8513619e-07 "h=0.0001"
EOD
$ida << EOD
35.03962 0.00062550511 "tol=0.0001"
78.723558 1.5759859e-05 "tol=1e-06"
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
