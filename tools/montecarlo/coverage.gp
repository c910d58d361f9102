# SPDX-License-Identifier: MIT
# Figure of the coverage Monte Carlo (tools/montecarlo/coverage.c, run.sh).
# gnuplot -e "d='DIR'" coverage.gp   reads DIR/coverage.csv, writes
# DIR/coverage_vs_trust.png: left, the 95 % ellipsoid coverage of the
# unflagged OK results against the true trust ratio (scenarios with at
# least 200 unflagged results); right, the fraction of OK results flagged
# untrusted.
if (!exists("d")) d = "docs/figures"
set datafile separator ","
set datafile missing NaN
set terminal pngcairo size 1400,600 font "DejaVu Sans,11" noenhanced
set grid
set logscale x
set format x "%g"
set xrange [5e-6:1.2]
set output d."/coverage_vs_trust.png"
c_ugdk = "#d62728"; c_sc = "#1f5fbf"; c_geo = "#2ca02c"
# est: "ugdk", "selfcal", "refined"; v: the value plotted
sel(est, v) = (strcol(6) eq est && $11 >= 200) ? v : NaN
self(est, v) = (strcol(6) eq est && $8 > 0) ? v : NaN
set multiplot layout 1,2 title "Coverage of the reported 95 % centre ellipsoid (chi-square 3 dof), 10^4 trials per scenario at N <= 100, 3000 at N = 1000, 1000 at N = 10^4"
set title "unflagged OK results (scenarios with >= 200 of them)"
set xlabel "true trust ratio sigma^2 / lambda_min(C)"
set ylabel "coverage"
set yrange [0.80:1.0]
set key bottom left box opaque
set arrow 1 from 0.35, graph 0 to 0.35, graph 1 nohead dt 2 lc rgb "gray30"
set label 1 "SFIT_COV_MAX_TRUST" at 0.3, graph 0.95 right
plot 0.92 with lines dt 3 lc rgb "black" notitle, 0.98 with lines dt 3 lc rgb "black" notitle, \
     0.95 with lines lc rgb "gray60" notitle, \
     d."/coverage.csv" using 5:(sel("ugdk", $12)) with points pt 7 ps 0.8 lc rgb c_ugdk title "UGDK, sigma known", \
     "" using ($5 * 1.08):(sel("selfcal", $12)) with points pt 5 ps 0.8 lc rgb c_sc title "self-calibrated (sandwich)", \
     "" using ($5 * 1.16):(sel("refined", $12)) with points pt 9 ps 0.8 lc rgb c_geo title "refined (sandwich + b b^T)"
set title "flagged untrusted (fraction of OK results)"
set ylabel "flagged fraction"
set yrange [-0.02:1.02]
set key top left box opaque
plot d."/coverage.csv" using 5:(self("ugdk", $9 / $8)) with points pt 7 ps 0.8 lc rgb c_ugdk title "UGDK, sigma known", \
     "" using ($5 * 1.08):(self("selfcal", $9 / $8)) with points pt 5 ps 0.8 lc rgb c_sc title "self-calibrated", \
     "" using ($5 * 1.16):(self("refined", $9 / $8)) with points pt 9 ps 0.8 lc rgb c_geo title "refined"
unset multiplot
