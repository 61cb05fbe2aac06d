# Frames for papers and films: a 3D rotating drum, a third full of glass beads, turning about
# its horizontal axis. The frames keep one colour range and one framing for the whole series
# (speed over 0 to the drum's rim speed, in m/s, with a legend), and a last frame cuts the bed
# open along the axis to show its force chains. Headless (OSMesa); a run of well under a minute.
#
#   build/demlab examples/drum3d.tcl ?folder?
#
# folder: where the frames go (default: frames3d): drum_000000.jpg ... and drum-chains.jpg.

set dir [expr {[llength $argv] ? [lindex $argv 0] : "frames3d"}]

source [file join [file dirname [info script]] drum3d_scene.tcl]
sim run -time 0.1 -quiet -progress 0

# Turn the drum about its axis and film it: a frame every 0.3 s, one colour range fixed
# by hand (0 to the rim speed) and the first frame's automatic framing (the series' default).
wall set $drum -angularvelocity [list 0 $omega 0]
file mkdir $dir
foreach f [glob -nocomplain -directory $dir drum_*.jpg] {file delete $f}
snapshot every -time 0.3 -dir $dir -format jpeg -quality 85 -size 480x360 -color speed \
    -range [list 0 [expr {$omega * $R}]] -title "rotating drum, $omega rad/s"
sim run -time 0.31 -quiet -progress 0
set frames [dict get [lindex [snapshot list] 0] frames]
snapshot off
foreach f [glob -directory $dir frame_*.jpg] {
    file rename -force $f [file join $dir [string map {frame_ drum_} [file tail $f]]]
}

# The bed cut open along the axis (the front half left out), walls hidden, coloured by each
# bead's contact-force magnitude, with the force chains above the mean drawn over it.
snapshot write [file join $dir drum-chains.jpg] -size 480x360 -position {0.03 -0.12 0.01} \
    -lookat {0 0 -0.018} -fov 30 -walls off -clip {0 0 0 0 -1 0} \
    -color contactforce -chains on -chainmin 1 -quality 90 -title "contact forces, front half cut away"
puts [format "%d grains; %d frames and drum-chains.jpg in %s" [element count] $frames \
    [file normalize $dir]]
