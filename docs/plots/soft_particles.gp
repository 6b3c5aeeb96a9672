# Run time against error of the smoke's off-screen particles (docs/SOFT_PARTICLES.md):
#   gnuplot docs/plots/soft_particles.gp        (from the repository's root; gnuplot-nox, .ci/setup
#                                                with RASTER_WITH_DOCS=1)
# reads docs/plots/soft_particles.dat, the output of
#   build/bin/raster bench soft-particles --frames 3 > docs/plots/soft_particles.dat
# (columns: count mode factor edge_fix ms_median flip_mean rmse band_flip outside_flip band_max
# outside_max band_share) and writes docs/figures/soft_particles_time_error.png.
set terminal pngcairo size 1100,420 font "DejaVu Sans,10"
set output "docs/figures/soft_particles_time_error.png"
data = "docs/plots/soft_particles.dat"
modes = "full half half_fix quarter quarter_fix"
titles = "full ½ ½+fix ¼ ¼+fix"
set multiplot layout 1,2
set logscale xy
set grid
set xrange [700:150000]
set key top left
set xlabel "particles"
set ylabel "frame time, ms (median)"
set title "Frame time, 1280×720, 2 threads"
# Rows come count by count, five modes each, in the order of `modes`: row i of each five is mode i.
plot for [i=1:5] data every 5::(i-1) using 1:5 with linespoints pt 7 lc i title word(titles, i)
set ylabel "mean FLIP error against full resolution"
set title "Error: whole frame (solid), band at depth edges (dashed)"
set yrange [5e-5:0.1]
set key bottom left
plot for [i=2:5] data every 5::(i-1) using 1:6 with linespoints pt 7 lc i title word(titles, i), \
     for [i=2:5] data every 5::(i-1) using 1:8 with linespoints pt 6 dt 2 lc i notitle
unset multiplot
