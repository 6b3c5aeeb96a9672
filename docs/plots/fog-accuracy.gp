# Drawn by raster bench fog-accuracy from fog-accuracy-points.csv: gnuplot fog-accuracy.gp
set terminal pngcairo size 1500,460 font "DejaVu Sans,10"
set output "fog-accuracy.png"
set datafile separator ","
set multiplot layout 1,3
set logscale xy
set grid
set yrange [0.5:3e13]
set ytics ("0" 1, "10" 11, "10^3" 1001, "10^6" 1e6, "10^9" 1e9, "NaN, ∞" 1e13)
set ylabel "worst error in float ulps, 1 + ulps"
set key top right
y(e) = e >= 1e29 ? 1e13 : (e > 1e12 ? 1e12 : 1 + e)
pick(p, f) = (strcol(1) eq p && strcol(2) eq f)
# μ = 0 and σ0 = 0 are drawn at 1e-35.
x0(x) = x == 0 ? 1e-35 : x
set xrange [3e-36:3e31]
set format x "10^{%L}"
set xlabel "extinction μ, 1/m (0 at the left edge)"
set title "Homogeneous L, worst over q, L0, s"
plot for [f in "raster lecture floor"] "fog-accuracy-points.csv" using (pick("homogeneous", f) ? x0($3) : NaN):(y($4)) with linespoints pt 7 title f
set xrange [1e-8:100]
set format x "10^{%L}"
set xlabel "distance s, m (b = 1, y0 = 0, dy = ±1)"
set title "Height fog τ along a ray, worse of up and down"
plot for [f in "raster unreal lecture"] "fog-accuracy-points.csv" using (pick("tau-sweep", f) ? $3 : NaN):(y($4)) with lines lw 2 title f
set xrange [3e-36:3e31]
set key center right
set xlabel "extinction σ0, 1/m (0 at the left edge)"
set title "Height-fog L, worst over q, L0, b, y0, dy, s"
plot for [f in "raster unreal floor lecture slide"] "fog-accuracy-points.csv" using (pick("height-fog", f) ? x0($3) : NaN):(y($4)) with linespoints pt 7 title f
unset multiplot
