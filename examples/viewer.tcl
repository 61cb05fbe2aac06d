# The viewer on a live scene: a 3D drum, a third full of glass beads, turning about its
# horizontal axis, with a series of its kinetic energy for the plot pane. Open it, then drag to
# turn the camera, click a bead to see it, press Play.
#
#   build/demlab examples/viewer.tcl          (the window stays until it is closed)
#   or at the console:  source examples/viewer.tcl
#
# Needs an X display (or xvfb-run); scripts/viewer-screenshots takes the README's pictures of
# this scene this way.

set R 0.04            ;# drum radius, m
set L 0.015           ;# half its length along the axis (y), m
set r 0.003           ;# grain radius, m

sim new -dim 3
material add glass -density 2500 -young 2e6 -poisson 0.3 -restitution 0.5 -friction 0.4
behavior add gravity -g {0 0 -9.81}
wall add plane -point [list 0 [expr {-$L}] 0] -normal {0 1 0} -name front
wall add plane -point [list 0 $L 0] -normal {0 -1 0} -name back
set drum [wall add drum -radius $R -axis {0 1 0} -halflength $L -name drum]
sim timestep auto -fraction 0.25
set a [expr {$L - 1.2 * $r}]
foreach seed {1 2 3} {
    pack random -region [list box [list -0.026 -$a -0.024] [list 0.026 $a 0.01]] \
        -radius [list uniform [expr {0.9 * $r}] $r] -count 80 -seed $seed -tries 5000
    sim run -time 0.12 -quiet -progress 0
}
wall set $drum -angularvelocity {0 3 0}
series every -quantities {time kinetic rotational contacts} -time 0.005
viewer open -size 640x480 -color speed

# As a script (not sourced at the console), keep the window until it is closed.
if {[info exists argv0] && [file tail $argv0] eq "viewer.tcl" && [info script] eq $argv0} {
    bind .demlab_viewer <Destroy> {if {"%W" eq ".demlab_viewer"} {set ::viewerDone 1}}
    vwait ::viewerDone
}
