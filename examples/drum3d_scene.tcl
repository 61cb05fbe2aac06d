# The 3D drum of drum3d.tcl and viewer.tcl: radius R, half length L along y, a third full of
# 240 glass beads of radius about r, settled; the drum wall's id in $drum and the drum speed in
# $omega (rad/s, not yet applied). Sourced by both.

set R 0.04            ;# drum radius, m
set L 0.015           ;# half its length along the axis (y), m
set r 0.003           ;# grain radius, m
set omega 3.0         ;# drum speed, rad/s: a rim speed of omega R = 0.12 m/s

sim new -dim 3
material add glass -density 2500 -young 2e6 -poisson 0.3 -restitution 0.5 -friction 0.4
behavior add gravity -g {0 0 -9.81}
wall add plane -point [list 0 [expr {-$L}] 0] -normal {0 1 0} -name front
wall add plane -point [list 0 $L 0] -normal {0 -1 0} -name back
set drum [wall add drum -radius $R -axis {0 1 0} -halflength $L -name drum]
sim timestep auto -fraction 0.25

# Grains dropped in three layers into a box in the lower half (its corners within R - r of the
# axis, clear of the end walls), each let settle before the next.
set a [expr {$L - 1.2 * $r}]
foreach seed {1 2 3} {
    pack random -region [list box [list -0.026 -$a -0.024] [list 0.026 $a 0.01]] \
        -radius [list uniform [expr {0.9 * $r}] $r] -count 80 -seed $seed -tries 5000
    sim run -time 0.12 -quiet -progress 0
}
