# Plots docs/drop_accuracy_table.csv (written by build/bench/drop_accuracy_bench) into
# docs/drop_accuracy.png:  gnuplot docs/drop_accuracy.gp   (run from the repository root)
set terminal pngcairo size 1400,560 font ",10"
set output "docs/drop_accuracy.png"
set datafile separator ","
set multiplot layout 1,2 title "Single-ball drop (1 cm steel, 20 cm): accuracy and cost against steps per contact"
set logscale xy
set grid
set key outside right top vertical font ",8"
set xlabel "steps per contact"
set ylabel "|error of eta_1| against exact / closed form / RK4 reference"
set format y "10^{%L}"
laws = "walton-braun walton-braun-plastic linear-dashpot hertz hertz-viscoelastic"
integrators = "verlet euler rk4"
filter(l, i) = sprintf("< awk -F, '$1==\"%s\" && $2==\"%s\"' docs/drop_accuracy_table.csv", l, i)
plot for [l=1:5] for [i=1:3] filter(word(laws,l), word(integrators,i)) \
     using 3:($4 > 1e-15 ? $4 : 1e-15) with linespoints lc l dt i pt (i+5) \
     title sprintf("%s %s", word(laws,l), word(integrators,i))
set ylabel "CPU time per full drop (microseconds)"
set format y "%g"
set key off
plot for [l=1:5] for [i=1:3] filter(word(laws,l), word(integrators,i)) \
     using 3:6 with linespoints lc l dt i pt (i+5) title sprintf("%s %s", word(laws,l), word(integrators,i))
unset multiplot
