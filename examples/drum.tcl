# The demo: a rotating drum, half filled with grains of two sizes and two colours, seen from
# the front (2D). The grains start in two layers, large below and small on top; the turning drum
# mixes them, then sorts them again: the small ones gather in the core of the rolling bed (radial
# segregation), the large ones at its surface and along the wall. A frame is written every
# few hundredths of a simulated second, headless (OSMesa), into a folder.
#
#   build/demlab examples/drum.tcl ?folder? ?-short?
#
# folder: where the frames go (default: frames). -short: the same fill, then a few frames
# only (the test suite's form, so it runs the demo's own setup). Turn the frames into a film with, for example,
#   ffmpeg -framerate 25 -i frames/frame_%06d.png -pix_fmt yuv420p drum.mp4

set dir frames
set short 0
foreach a $argv {
    if {$a eq "-short"} {set short 1} else {set dir $a}
}

set R 0.05           ;# drum radius, m
set rLarge 0.0025    ;# grain radii, m: a size ratio of 2
set rSmall 0.00125
set omega 3.0        ;# drum speed, rad/s (about 2 s a turn; Froude number w^2 R / g = 0.05)
set turns [expr {$short ? 0.05 : 5}]
set frameEvery 0.04  ;# simulated seconds between frames (25 frames a second of simulated time)

sim new -dim 2
material add glass -density 2500 -young 2e6 -poisson 0.3 -restitution 0.5 -friction 0.4
behavior add gravity -g {0 -9.81}
set drum [wall add drum -radius $R -name drum]
sim timestep auto -fraction 0.25

# Fill in layers: large grains first, then small ones on top, each layer dropped into the
# lower part of the drum and let settle before the next. Each layer is a box inside the drum:
# its corners lie within R - r of the centre (pack random keeps grains apart from each other,
# not from walls; the watchdog stops a run whose grains start deep in a wall).
proc layer {tag radius count lo hi seed} {
    pack random -region [list box $lo $hi] -radius [list uniform [expr {0.95 * $radius}] $radius] \
        -count $count -tags $tag -seed $seed -tries 5000
    sim run -time 0.12 -quiet -progress 0
}
layer large $rLarge 32 {-0.03 -0.036} {0.03 -0.012} 1
layer large $rLarge 45 {-0.035 -0.03} {0.035 0.0} 2
layer large $rLarge 43 {-0.035 -0.02} {0.035 0.01} 3
layer small $rSmall 170 {-0.035 -0.01} {0.035 0.02} 4
layer small $rSmall 170 {-0.035 -0.005} {0.035 0.025} 5
layer small $rSmall 140 {-0.035 0.0} {0.035 0.03} 6
sim run -time [expr {$short ? 0.05 : 0.3}] -quiet -progress 0  ;# the last layer comes to rest
puts "[element count] grains ([llength [element list -tag large]] large, [llength [element list -tag small]] small), dt = [sim timestep] s"

# Turn the drum (counterclockwise) and film it.
wall set $drum -angularvelocity $omega
file mkdir $dir
foreach f [glob -nocomplain -directory $dir frame_*.png] {file delete $f}
snapshot every -time $frameEvery -dir $dir -size 960x720 -color tag -tags {large small} \
    -colormap categorical -legend 1
set T [expr {$turns * 2 * acos(-1) / $omega}]
set t0 [clock milliseconds]
sim run -time $T
set frames [dict get [lindex [snapshot list] 0] frames]
snapshot off
puts [format "%d frames in %s/ (frame_000000.png ... frame_%06d.png), %.1f s of simulated time, %.1f s wall" \
    $frames [file normalize $dir] [expr {$frames - 1}] [sim time] [expr {([clock milliseconds] - $t0) / 1000.0}]]
