# SPDX-License-Identifier: MIT
# Figure of the joint benchmark (tools/montecarlo/joint_bench.c, run.sh).
# gnuplot -e "d='DIR'" joint_bench.gp   reads DIR/joint_bench.csv, writes
# DIR/joint_bench.png: left, the mean centre error of a ball joint against
# the range of motion (moving parent, sigma 1 mm); middle, the coverage of
# the reported 95 % ellipsoid among unflagged results (same cells); right,
# the mean hinge-axis error against the flexion range with 2-5 degrees of
# out-of-axis motion (sigma 1 mm), and (right axis, dashed) the fraction of
# the pair default's hinge results flagged untrusted. Methods missing from
# the CSV are skipped.
if (!exists("d")) d = "docs/figures"
set datafile separator ","
set datafile missing NaN
set terminal pngcairo size 1500,520 font "DejaVu Sans,11" noenhanced
set grid
set output d."/joint_bench.png"
f = d."/joint_bench.csv"
# ball, moving parent, noise only, sigma s; hinge with wobble, sigma s
ball(m, s, v) = (strcol(1) eq "ball" && strcol(2) eq "moving" && $3 == 0 && $6 == s && strcol(7) eq m) ? v : NaN
hinge(m, s, v) = (strcol(1) eq "hinge" && $4 == 1 && $6 == s && strcol(7) eq m) ? v : NaN
cov(v) = (v >= 0) ? v : NaN
stats f using 0 nooutput
havepair = system("grep -c ',pair_default,' ".f) + 0 > 0
set multiplot layout 1,3 title "Joint benchmark: synthetic trials after Ehrig et al. 2006/2007, sigma = 1 mm"
set title "ball joint: mean centre error"
set xlabel "range of motion (deg)"
set ylabel "mean error (mm)"
set logscale y
set format y "%g"
set key top right box opaque
plot f using 5:(ball("mgdk", 1, $11)) with linespoints pt 7 lc rgb "#7f7f7f" title "MGDK (multi-marker sphere fit)", \
     "" using 5:(ball("mgdk_est", 1, $11)) with linespoints pt 6 lc rgb "#2ca02c" title "MGDK, sigma from residuals", \
     "" using 5:(ball("score", 1, $11)) with linespoints pt 5 lc rgb "#1f5fbf" title "SCoRE (double)", \
     "" using 5:(ball("score_eiv", 1, $11)) with linespoints pt 4 lc rgb "#9467bd" title "SCoRE, bias removed (double)", \
     "" using 5:(havepair ? ball("pair_default", 1, $11) : NaN) with linespoints pt 9 lw 2 lc rgb "#d62728" title "sfit_pair default"
set title "ball joint: 95 % ellipsoid coverage (unflagged)"
unset logscale y
set ylabel "coverage"
set yrange [0:1.05]
set key bottom right box opaque
plot 0.92 with lines dt 3 lc rgb "black" notitle, 0.98 with lines dt 3 lc rgb "black" notitle, \
     f using 5:(cov(ball("score", 1, $16))) with linespoints pt 5 lc rgb "#1f5fbf" title "SCoRE, sandwich", \
     "" using 5:(cov(ball("score_eiv", 1, $16))) with linespoints pt 4 lc rgb "#9467bd" title "SCoRE bias removed, sandwich", \
     "" using 5:(cov(ball("mgdk_sig", 1, $16))) with linespoints pt 6 lc rgb "#2ca02c" title "MGDK, true sigma", \
     "" using 5:(havepair ? cov(ball("pair_default", 1, $16)) : NaN) with linespoints pt 9 lw 2 lc rgb "#d62728" title "sfit_pair default"
set title "hinge, 2-5 deg out-of-axis motion: mean axis error"
set autoscale y
set logscale y
set xlabel "flexion range (deg)"
set ylabel "mean axis error (deg)"
set key bottom left box opaque
set y2label "flagged fraction (dashed)"
set y2range [0:1.05]
set y2tics 0.2
set ytics nomirror
plot f using 5:(hinge("mgdk", 1, $11)) with linespoints pt 7 lc rgb "#7f7f7f" title "MGDK planar (today's)", \
     "" using 5:(hinge("score", 1, $11)) with linespoints pt 5 lc rgb "#1f5fbf" title "SARA (double)", \
     "" using 5:(havepair ? hinge("pair_default", 1, $11) : NaN) with linespoints pt 9 lw 2 lc rgb "#d62728" title "sfit_pair default", \
     "" using 5:(havepair ? hinge("pair_default", 1, $10 / $8) : NaN) axes x1y2 with linespoints pt 9 dt 2 lc rgb "#d62728" title "sfit_pair default: flagged"
unset multiplot
