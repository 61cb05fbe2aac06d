# The viewer on a live scene: a 3D drum, a third full of glass beads, turning about its
# horizontal axis, with a series of its kinetic energy for the plot pane. Open it, then drag to
# turn the camera, click a bead to see it, press Play.
#
#   build/demlab examples/viewer.tcl          (the window stays until it is closed)
#   or at the console:  source examples/viewer.tcl
#
# Needs an X display (or xvfb-run); scripts/viewer-screenshots takes the README's pictures of
# this scene this way.

source [file join [file dirname [info script]] drum3d_scene.tcl]
wall set $drum -angularvelocity [list 0 $omega 0]
series every -quantities {time kinetic rotational contacts} -time 0.005
viewer open -size 640x480 -color speed

# As a script (not sourced at the console), keep the window until it is closed.
if {[info exists argv0] && [file tail $argv0] eq "viewer.tcl" && [info script] eq $argv0} {
    bind .demlab_viewer <Destroy> {if {"%W" eq ".demlab_viewer"} {set ::viewerDone 1}}
    vwait ::viewerDone
}
