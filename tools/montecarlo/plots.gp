# SPDX-License-Identifier: MIT
# Figures of the Monte Carlo validation (tools/montecarlo/run.sh calls it).
# gnuplot -e "d='DIR'" plots.gp   reads DIR/*.csv, writes DIR/*.png
if (!exists("d")) d = "docs/figures"
set datafile separator ","
set datafile missing NaN
set terminal pngcairo size 1200,800 font "DejaVu Sans,11" noenhanced
set key top right box opaque
set grid
c_gdke = "#1f5fbf"; c_ugdk = "#d62728"; c_geo = "#2ca02c"; c_crlb = "black"
sel(th, sg, est, v) = ($1 == th && $2 == sg && strcol(4) eq est) ? v : NaN

# ----------------------------------------------------------------------
# 1. Error versus N (chapter Fig. 19)
set output d."/error_vs_n.png"
set multiplot layout 2,3 title "Centre RMSE versus N: GDKE, UGDK (float library), ML fit (double), and sqrt(tr CRLB); r = 100 mm"
set logscale xy
set format y "%g"
set xlabel "N (samples)"
set ylabel "centre RMSE (mm)"
set xrange [7:14000]
array TH[6] = [180, 90, 60, 45, 30, 30]
array SG[6] = [5, 5, 2, 2, 0.5, 2]
do for [i=1:6] {
    th = TH[i]; sg = SG[i]
    ttl = (th == 180 ? "full sphere" : sprintf("cap %g deg", th)) . sprintf(", sigma %g mm", sg)
    set title ttl
    # 1/sqrt(N) guide through the CRLB at N = 10000
    stats d."/scenarios.csv" using (sel(th, sg, "ugdk", ($3 == 10000 ? $17 : NaN))) nooutput
    k = STATS_max * 100.0
    set key top right font ",9"
    plot d."/scenarios.csv" using 3:(sel(th, sg, "gdke", $16)) with linespoints lc rgb c_gdke pt 5 title "GDKE", \
         "" using 3:(sel(th, sg, "ugdk", $16)) with linespoints lc rgb c_ugdk pt 7 title "UGDK", \
         "" using 3:(sel(th, sg, "geo", $16)) with linespoints lc rgb c_geo pt 9 title "ML (geometric)", \
         "" using 3:(sel(th, sg, "ugdk", $17)) with lines lc rgb c_crlb lw 2 title "sqrt(tr CRLB)", \
         k / sqrt(x) with lines dt 2 lc rgb "gray40" title "slope 1/sqrt(N)"
}
unset multiplot
unset logscale
set xrange [*:*]
set yrange [*:*]

# ----------------------------------------------------------------------
# 2. One hundred data sets: GDKE, UGDK, ML (chapter Fig. 20)
set terminal pngcairo size 900,800 font "DejaVu Sans,11" noenhanced
set output d."/compare100.png"
set title "100 data sets of N = 100, cap 45 deg, sigma 5 mm (rho = 0.26): centre errors\n(ML green, UGDK red, GDKE blue; black: 95% CRLB ellipse around the truth)"
set xlabel "lateral error (mm)"
set ylabel "error along the cap axis (mm), + = towards the samples"
set size ratio -1
set key top left
set xrange [-40:40]
set yrange [-35:45]
plot d."/compare_trials.csv" using (strcol(2) eq "gdke" ? $3 : NaN):4 with points pt 5 ps 0.8 lc rgb c_gdke title "GDKE", \
     "" using (strcol(2) eq "ugdk" ? $3 : NaN):4 with points pt 7 ps 0.8 lc rgb c_ugdk title "UGDK", \
     "" using (strcol(2) eq "geo" ? $3 : NaN):4 with points pt 9 ps 0.9 lc rgb c_geo title "ML (geometric)", \
     d."/compare_ellipses.csv" using (strcol(1) eq "crlb95" ? $2 : NaN):3 with lines lw 2 lc rgb c_crlb title "95% CRLB (mean over the 100 sets)", \
     "" using (strcol(1) eq "predicted_gdke_bias" ? $2 : NaN):3 with points pt 3 ps 3 lw 2 lc rgb c_gdke title "predicted GDKE bias rho r (1 + cos theta)/2", \
     "+" using (0):(0) with points pt 1 ps 3 lw 3 lc rgb "black" title "true centre"

# ----------------------------------------------------------------------
# 3. One data set and its error ellipse (chapter Fig. 18)
set output d."/ellipse.png"
set title "One data set (N = 100, cap 45 deg, sigma 5 mm): estimates and the 95% error ellipse\nof the UGDK centre (CRLB evaluated at the fitted sphere, i.e. from the data alone)"
set xrange [-30:30]
set yrange [-30:30]
plot d."/ellipse_one.csv" using (strcol(1) eq "ellipse" ? $2 : NaN):3 with lines lw 2 lc rgb c_ugdk title "95% ellipse around UGDK", \
     "" using (strcol(1) eq "gdke" ? $2 : NaN):3 with points pt 5 ps 2 lc rgb c_gdke title "GDKE", \
     "" using (strcol(1) eq "ugdk" ? $2 : NaN):3 with points pt 7 ps 2 lc rgb c_ugdk title "UGDK", \
     "" using (strcol(1) eq "geo" ? $2 : NaN):3 with points pt 9 ps 2 lc rgb c_geo title "ML (geometric)", \
     "" using (strcol(1) eq "truth" ? $2 : NaN):3 with points pt 1 ps 3 lw 3 lc rgb "black" title "true centre"
set size noratio
set xrange [*:*]
set yrange [*:*]

# ----------------------------------------------------------------------
# 4. UGDK versus the CRLB as sigma grows towards r (chapter Fig. 21)
set terminal pngcairo size 1200,900 font "DejaVu Sans,11" noenhanced
set output d."/sigma_vs_crlb.png"
set multiplot layout 2,2 title "Centre RMSE as sigma grows towards r = 100 mm (N = 1000, 300 trials); dashed: Leontief limit rho0 = sigma^2/lambda_min(C0) = 1"
set logscale xy
set xrange [0.8:120]
set xlabel "sigma (mm)"
set key top left font ",9"
do for [th in "180 60"] {
    t = th + 0
    stats d."/sigma.csv" using (($1 == t) ? $8 : NaN) nooutput
    sl = STATS_max
    set arrow 1 from sl, graph 0 to sl, graph 1 nohead dt 2 lw 2 lc rgb "gray30"
    set title (t == 180 ? "full sphere" : sprintf("cap %g deg", t)) . sprintf(": RMSE (Leontief limit sigma = %.1f mm)", sl)
    set ylabel "centre RMSE (mm)"
    set yrange [*:*]
    plot d."/sigma.csv" using 2:(($1 == t && strcol(4) eq "gdke") ? $9 : NaN) with linespoints lc rgb c_gdke pt 5 title "GDKE", \
         "" using 2:(($1 == t && strcol(4) eq "ugdk") ? $9 : NaN) with linespoints lc rgb c_ugdk pt 7 title "UGDK", \
         "" using 2:(($1 == t && strcol(4) eq "geo") ? $9 : NaN) with linespoints lc rgb c_geo pt 9 title "ML (geometric)", \
         "" using 2:(($1 == t && strcol(4) eq "ugdk") ? $10 : NaN) with lines lw 2 lc rgb c_crlb title "sqrt(tr CRLB)"
}
do for [th in "180 60"] {
    t = th + 0
    stats d."/sigma.csv" using (($1 == t) ? $8 : NaN) nooutput
    sl = STATS_max
    set arrow 1 from sl, graph 0 to sl, graph 1 nohead dt 2 lw 2 lc rgb "gray30"
    set title (t == 180 ? "full sphere" : sprintf("cap %g deg", t)) . ": RMSE / sqrt(tr CRLB)"
    set ylabel "RMSE / sqrt(tr CRLB)"
    set yrange [0.8:*]
    plot d."/sigma.csv" using 2:(($1 == t && strcol(4) eq "gdke") ? $11 : NaN) with linespoints lc rgb c_gdke pt 5 title "GDKE", \
         "" using 2:(($1 == t && strcol(4) eq "ugdk") ? $11 : NaN) with linespoints lc rgb c_ugdk pt 7 title "UGDK", \
         "" using 2:(($1 == t && strcol(4) eq "geo") ? $11 : NaN) with linespoints lc rgb c_geo pt 9 title "ML (geometric)", \
         1.1 with lines dt 3 lc rgb "black" title "1.10"
}
unset multiplot
unset arrow 1
unset logscale
set xrange [*:*]
set yrange [*:*]

# ----------------------------------------------------------------------
# 5. GDKE's cap bias against rho r (1 + cos theta)/2
set terminal pngcairo size 1200,600 font "DejaVu Sans,11" noenhanced
set output d."/gdke_cap_bias.png"
set multiplot layout 1,2 title "GDKE bias along the cap axis (N = 10000, 200 trials per point): measured vs rho r (1 + cos theta)/2"
set logscale xy
set xrange [0.4:12]
set xlabel "sigma (mm)"
set ylabel "axial bias (mm)"
set key top left font ",9"
set title "measured (points, +-1 SE) and predicted (lines)"
set key bottom right font ",9"
set yrange [0.0005:1000]
array CT[4] = [90, 60, 45, 30]
array CC[4] = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728"]
plot for [i=1:4] d."/capbias.csv" using 2:(($1 == CT[i]) ? $10 : NaN):11 with yerrorbars pt 7 lc rgb CC[i] title sprintf("cap %d deg", CT[i]), \
     for [i=1:4] "" using 2:(($1 == CT[i]) ? $8 : NaN) with lines lw 2 lc rgb CC[i] notitle, \
     for [i=1:4] "" using 2:(($1 == CT[i]) ? $9 : NaN) with lines dt 2 lc rgb CC[i] notitle, \
     NaN with lines lw 2 lc rgb "black" title "predicted, rho = trust ratio", \
     NaN with lines dt 2 lc rgb "black" title "predicted with rho0 instead"
unset logscale y
set logscale x
set ylabel "(measured - predicted) / predicted"
set yrange [-0.12:0.12]
set key top right font ",9"
set title "(measured - predicted)/predicted, trust-ratio rho; +-5% dashed"
plot for [i=1:4] d."/capbias.csv" using 2:(($1 == CT[i]) ? ($10 - $8) / $8 : NaN):($11 / $8) with yerrorbars pt 7 lc rgb CC[i] title sprintf("cap %d deg", CT[i]), \
     0.05 with lines dt 2 lc rgb "black" notitle, -0.05 with lines dt 2 lc rgb "black" notitle, \
     0 with lines lc rgb "gray50" notitle
unset multiplot
