# A convergence study from a script: a glass sphere hits a floor head-on (Hertz-Mindlin, material
# restitution 0.5) and rebounds. The study runs the impact at a ladder of time steps with both
# integrators, measures the rebound (the sphere's height and vertical velocity once it has left
# the floor) and, there being no closed form for the damped Hertz impact, compares each run with
# the finest run of the same integrator. It prints the table (dt, integrator, steps, wall time,
# energy residual, error, observed order), writes it as CSV and draws the work-precision plot
# (error against wall time and against dt, log-log) with gnuplot.
#
#   build/demlab examples/convergence.tcl ?plot.png? ?-short?
#
# plot.png: where the plot goes (default: convergence.png; the CSV goes beside it, .csv).
# -short: three time steps instead of seven (the test suite's form, well under a second).
# Each case runs three times (-repeat 3) and keeps its shortest wall time, which steadies the
# work-precision plot on a busy machine.

set png convergence.png
set short 0
foreach a $argv {
    if {$a eq "-short"} {set short 1} else {set png $a}
}
set csv [file rootname $png].csv

set R 0.005       ;# sphere radius, m
set rho 2500.0    ;# density, kg/m^3
set E 1e8         ;# Young's modulus, Pa
set nu 0.3
set v0 1.0        ;# impact speed, m/s

# Hertz's contact time of the elastic impact on a floor of the same material (about 0.12 ms):
# 2.87 (m^2 / (R E*^2 v0))^(1/5), with E* = E / (2 (1 - nu^2)) for two bodies of one material.
set m [expr {$rho * 4.0 / 3.0 * acos(-1) * $R ** 3}]
set Estar [expr {$E / (2 * (1 - $nu * $nu))}]
set tc [expr {2.87 * ($m * $m / ($R * $Estar * $Estar * $v0)) ** 0.2}]

# Builds the scene afresh: the study calls it once per run, then sets the integrator and dt.
proc hertzImpact {} {
    global R rho E nu v0 tc
    sim new -dim 3
    material add glass -density $rho -young $E -poisson $nu -restitution 0.5 -friction 0
    law default hertz_mindlin
    wall add plane -normal {0 0 1}
    # Touching the floor: the contact starts with the first step, at a step boundary for every dt.
    element add -radius $R -position [list 0 0 $R] -velocity [list 0 0 -$v0]
    # The coarsest step of the study: -refine starts here and halves it.
    sim timestep [expr {$tc / 20}]
}

# The coefficient of restitution: rebound speed over impact speed, once the contact is over.
proc restitution {} {
    expr {[lindex [element get 0 -velocity] 2] / $::v0}
}

# Three contact times: the sphere has left the floor well before the end of every run.
set rows [study convergence -scene hertzImpact -time [expr {3 * $tc}] \
    -refine [expr {$short ? 3 : 7}] -measure restitution -relative -repeat 3 -csv $csv -plot $png]

puts [format "contact time %.4g s; restitution of the finest synchronized run %.6f" $tc \
    [dict get [lindex $rows 0] reference]]
puts "wrote $png and $csv"
