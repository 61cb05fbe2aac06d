# The body of scripts/viewer-screenshots: drives the viewer as a user would (synthetic mouse
# events on the picture, the buttons' own commands) and captures the window. argv: the folder.
package require Tk
set out [lindex $argv 0]

# Returns a photo of the X window id, captured by xwd (ZPixmap, 24 or 32 bits per pixel,
# little-endian as Xvfb writes it).
proc capture {id} {
    set chan [open |[list xwd -silent -id $id] rb]
    set data [read $chan]
    close $chan
    binary scan $data IIIIIIIIIIIIIIIIIIII \
        headerSize version format depth width height xoffset byteOrder unit bitOrder pad bpp \
        bytesPerLine visualClass red green blue bitsPerRgb colormapEntries ncolors
    set start [expr {$headerSize + 12 * $ncolors}]
    set img [image create photo -width $width -height $height]
    set step [expr {$bpp / 8}]
    for {set y 0} {$y < $height} {incr y} {
        set row [string range $data [expr {$start + $y * $bytesPerLine}] \
                     [expr {$start + ($y + 1) * $bytesPerLine - 1}]]
        binary scan $row cu* bytes
        set line {}
        for {set x 0} {$x < $width} {incr x} {
            set k [expr {$x * $step}]
            lappend line [format #%02x%02x%02x [lindex $bytes [expr {$k + 2}]] \
                              [lindex $bytes [expr {$k + 1}]] [lindex $bytes $k]]
        }
        $img put [list $line] -to 0 $y
    }
    return $img
}
proc shoot {file} {
    update
    after 300
    update
    set img [capture [winfo id .demlab_viewer]]
    $img write $file -format png
    image delete $img
    puts "wrote $file"
}
# Drags on the picture from (x0, y0) by (dx, dy) with button 1.
proc drag {x0 y0 dx dy} {
    set v .demlab_viewer.view
    event generate $v <ButtonPress-1> -x $x0 -y $y0 -button 1
    for {set k 1} {$k <= 10} {incr k} {
        event generate $v <B1-Motion> -x [expr {$x0 + $dx * $k / 10}] \
            -y [expr {$y0 + $dy * $k / 10}] -state 256
    }
    event generate $v <ButtonRelease-1> -x [expr {$x0 + $dx}] -y [expr {$y0 + $dy}] -button 1 -state 256
    update
}
proc click {x y} {
    set v .demlab_viewer.view
    event generate $v <ButtonPress-1> -x $x -y $y -button 1
    event generate $v <ButtonRelease-1> -x $x -y $y -button 1
    update
}
# Clicks the first of the points {x y ...} where the picture shows an element, plots the first
# series' kinetic energy, and writes the window to file.
proc selectPlotShoot {points file} {
    foreach {x y} $points {
        if {[viewer pick $x $y {*}[::demlab::viewer::Options]] ne ""} {click $x $y; break}
    }
    set ::demlab::viewer::plotted "[dict get [lindex [series list] 0] id] kinetic"
    ::demlab::viewer::Plot
    shoot $file
}

# 3D: the drum turning, played for 0.3 s of simulated time from the window.
set argv0 ""
source examples/viewer.tcl
.demlab_viewer.bar.play invoke
while {[dict get [sim info] time] < 0.66} {update; after 20}
.demlab_viewer.bar.pause invoke
update
drag 320 240 -60 -25
# A bead near the picture's centre.
selectPlotShoot {300 330 320 320 280 340 340 300} [file join $out viewer-3d.png]
viewer close

# 2D: discs settling in a box, coloured by the force on each.
sim new -dim 2
material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5
behavior add gravity -g {0 -9.81}
wall add plane -point {0 0} -normal {0 1}
wall add plane -point {-0.05 0} -normal {1 0}
wall add plane -point {0.05 0} -normal {-1 0}
pack random -region {box {-0.048 0.002} {0.048 0.098}} -radius {uniform 0.0015 0.0025} \
    -count 300 -seed 4 -tries 5000
sim timestep auto
series every -quantities {time kinetic contacts} -time 0.002
sim run -time 0.5 -quiet -progress 0
viewer open -size 480x480 -color contactforce
update
selectPlotShoot {200 300 210 300 190 310 220 290} [file join $out viewer-2d.png]
viewer close
exit
