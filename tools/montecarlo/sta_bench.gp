# SPDX-License-Identifier: MIT
# Figure of the skin-motion benchmark (tools/montecarlo/sta_bench.c).
# gnuplot -e "d='DIR'" sta_bench.gp   reads DIR/sta_bench.csv, writes
# DIR/sta_bench.png: left, the coverage of the reported 95 % ellipsoid among
# unflagged results against the skin motion's amplitude (every ball cell;
# the band 92-98 % dotted); middle, the median of d' C^-1 d (2.37 for a
# true 95 % ellipsoid, 0.8 the floor asked); right, the median reported
# standard deviation (largest axis) against the mean error, per cell.
if (!exists("d")) d = "docs/figures"
set datafile separator ","
set terminal pngcairo size 1500,500 font "DejaVu Sans,11" noenhanced
set grid
set output d."/sta_bench.png"
f = d."/sta_bench.csv"
ball(m, v) = (strcol(2) eq m && strcol(1) eq ("ball ".m)) ? v : NaN
set multiplot layout 1,3 title "sfit_pair under skin motion (STA): 500 frames, RoM 20-60 deg, sigma 0.5-1 mm, 8000 trials per ball cell"
set title "95 % ellipsoid coverage among unflagged results"
set xlabel "skin motion (mm rms at a 30 deg swing)"
set ylabel "coverage"
set yrange [0.85:1.01]
set xrange [-0.5:11]
set key bottom left box opaque
plot 0.92 with lines dt 3 lc rgb "black" notitle, 0.98 with lines dt 3 lc rgb "black" notitle, \
     f using ($5 - 0.15):(ball("rigid", $10)) with points pt 7 lc rgb "#1f5fbf" title "rigid cluster motion", \
     "" using ($5 + 0.15):(ball("marker", $10)) with points pt 5 lc rgb "#d62728" title "per-marker motion + drift", \
     "" using 5:(ball("none", $10)) with points pt 9 lc rgb "#2ca02c" title "marker noise only"
set title "median d' C^-1 d (true ellipsoid: 2.37)"
set ylabel "median"
set yrange [0:3]
plot 2.366 with lines dt 2 lc rgb "black" notitle, 0.8 with lines dt 3 lc rgb "black" notitle, \
     f using ($5 - 0.15):(ball("rigid", $13)) with points pt 7 lc rgb "#1f5fbf" title "rigid", \
     "" using ($5 + 0.15):(ball("marker", $13)) with points pt 5 lc rgb "#d62728" title "per-marker", \
     "" using 5:(ball("none", $13)) with points pt 9 lc rgb "#2ca02c" title "noise only"
set title "reported SD (median, largest axis) against the error"
set xlabel "mean centre error (mm)"
set ylabel "reported SD (mm)"
set logscale xy
set xrange [0.1:40]
set yrange [0.1:60]
set key top left box opaque
plot x with lines dt 2 lc rgb "black" title "SD = error", \
     f using (ball("rigid", $11)):(ball("rigid", $14)) with points pt 7 lc rgb "#1f5fbf" title "rigid", \
     "" using (ball("marker", $11)):(ball("marker", $14)) with points pt 5 lc rgb "#d62728" title "per-marker", \
     "" using (ball("none", $11)):(ball("none", $14)) with points pt 9 lc rgb "#2ca02c" title "noise only"
unset multiplot
