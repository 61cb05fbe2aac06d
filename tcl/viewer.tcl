# The viewer window: Tcl over Tk, evaluated by `viewer open` (src/cmd/commands/viewer.cpp) the
# first time a viewer is opened, so a scene without one loads no Tk. The picture is the
# snapshots' renderer's frame (`viewer frame`) put into a Tk photo; a click asks `viewer pick`
# with the same options, so what is picked is what was drawn. The camera is kept here as a dict
# (position, lookat, up, fov, viewheight, orthographic), empty for the automatic framing.
#
# Every demlab command is called by its full name (::demlab::sim ...): this namespace must not
# see ::demlab's `pack`, which would hide Tk's.

namespace eval ::demlab::viewer {
    variable w .demlab_viewer
    variable picture demlab_viewer_picture
    variable selection {}
    variable camera {}
    variable colour speed
    variable width 640
    variable height 480
    variable fps 5
    variable playing 0
    variable inRun 0
    variable chunk 1
    variable drag {}
    variable status ""
    variable seen -1
    variable frames 0
    variable plotted ""
    variable poll ""
    variable dim 3
    variable overlay {}
}

# Opens the window (or raises it) with a picture of width x height pixels, redrawn during runs at
# most fps times a second, coloured by colour, with or without legend and time stamp. Returns
# nothing.
proc ::demlab::viewer::Open {size fps colour legend timestamp} {
    variable w
    variable picture
    lassign [split $size x] ::demlab::viewer::width ::demlab::viewer::height
    set ::demlab::viewer::fps $fps
    set ::demlab::viewer::colour $colour
    set ::demlab::viewer::overlay [list -legend $legend -timestamp $timestamp]
    if {[winfo exists $w]} {
        $picture configure -width $::demlab::viewer::width -height $::demlab::viewer::height
        raise $w
        Refresh
        return
    }
    # A new window starts with the automatic framing and nothing selected.
    set ::demlab::viewer::camera {}
    set ::demlab::viewer::selection {}
    # An empty main window (the demlab console's) is hidden; a wish user's own is left alone.
    if {[llength [winfo children .]] == 0} {wm withdraw .}
    toplevel $w
    wm title $w "demlab viewer"
    wm protocol $w WM_DELETE_WINDOW {::demlab::viewer close}
    image create photo $picture -width $::demlab::viewer::width -height $::demlab::viewer::height

    ttk::frame $w.bar
    ttk::button $w.bar.play -text Play -command ::demlab::viewer::Play
    ttk::button $w.bar.pause -text Pause -command ::demlab::viewer::Pause
    ttk::button $w.bar.step -text Step -command ::demlab::viewer::Step
    ttk::label $w.bar.cl -text "  Colour by"
    ttk::combobox $w.bar.colour -state readonly -width 13 \
        -textvariable ::demlab::viewer::colour \
        -values {speed force contactforce spin radius id material}
    bind $w.bar.colour <<ComboboxSelected>> ::demlab::viewer::Draw
    ttk::button $w.bar.fit -text "Fit view" -command {::demlab::viewer::SetCamera {}}
    grid $w.bar.play $w.bar.pause $w.bar.step $w.bar.cl $w.bar.colour $w.bar.fit -padx 2 -pady 2

    label $w.view -image $picture -borderwidth 0 -highlightthickness 0 -cursor crosshair
    bind $w.view <ButtonPress-1> {::demlab::viewer::Press %x %y %s 1}
    bind $w.view <ButtonPress-2> {::demlab::viewer::Press %x %y %s 2}
    bind $w.view <B1-Motion> {::demlab::viewer::Motion %x %y}
    bind $w.view <B2-Motion> {::demlab::viewer::Motion %x %y}
    bind $w.view <ButtonRelease-1> {::demlab::viewer::Release %x %y %s}
    bind $w.view <ButtonRelease-2> {::demlab::viewer::Release %x %y %s}
    bind $w.view <Button-4> {::demlab::viewer::Zoom 1}
    bind $w.view <Button-5> {::demlab::viewer::Zoom -1}
    bind $w.view <MouseWheel> {::demlab::viewer::Zoom [expr {%D > 0 ? 1 : -1}]}

    ttk::frame $w.side
    ttk::label $w.side.title -text "Selected element"
    text $w.side.info -width 52 -height 17 -wrap none -font TkFixedFont -state disabled
    ttk::label $w.side.pt -text "Series"
    ttk::combobox $w.side.series -state readonly -width 30 \
        -textvariable ::demlab::viewer::plotted -postcommand ::demlab::viewer::SeriesChoices
    bind $w.side.series <<ComboboxSelected>> ::demlab::viewer::Plot
    canvas $w.side.plot -width 320 -height 170 -background white -highlightthickness 0
    grid $w.side.title -sticky w
    grid $w.side.info -sticky nsew
    grid $w.side.pt -sticky w
    grid $w.side.series -sticky ew
    grid $w.side.plot -sticky nsew

    ttk::label $w.status -textvariable ::demlab::viewer::status -anchor w
    grid $w.bar - -sticky w
    grid $w.view $w.side -sticky nw
    grid $w.status - -sticky ew
    Refresh
    Poll
}

# Closes the window. Returns 1 if it was open.
proc ::demlab::viewer::Close {} {
    variable w
    variable playing 0
    variable poll
    after cancel $poll
    if {![Shown]} {return 0}
    destroy $w
    return 1
}

# Returns 1 if the window is open (0 too where Tk is not loaded: `viewer selection` works
# without a window).
proc ::demlab::viewer::Shown {} {
    expr {[info commands ::winfo] ne "" && [winfo exists $::demlab::viewer::w]}
}

# Returns the drawing options of the current picture (size, colour, camera).
proc ::demlab::viewer::Options {} {
    variable camera
    set o [list -size ${::demlab::viewer::width}x$::demlab::viewer::height \
               -color $::demlab::viewer::colour -antialias 1 {*}$::demlab::viewer::overlay]
    if {[llength $::demlab::viewer::selection]} {
        lappend o -highlight $::demlab::viewer::selection
    }
    if {[dict size $camera] == 0} {return $o}
    lassign [dict get $camera lookat] x y z
    if {[Dim] == 2} {
        return [concat $o [list -position [list $x $y 1] -lookat [list $x $y 0] \
                               -viewheight [dict get $camera viewheight]]]
    }
    lappend o -position [dict get $camera position] -lookat [dict get $camera lookat] \
        -up [dict get $camera up] -fov [dict get $camera fov]
    if {[dict get $camera orthographic]} {
        lappend o -ortho -viewheight [dict get $camera viewheight]
    }
    return $o
}

# Returns the scene's dimension as the last refresh saw it (sim info is refused during runs).
proc ::demlab::viewer::Dim {} {
    return $::demlab::viewer::dim
}

# Draws the scene into the picture; a failure (no scene yet) shows in the status line.
proc ::demlab::viewer::Draw {} {
    variable w
    variable picture
    if {![Shown]} return
    set failed [catch {::demlab::viewer frame {*}[Options]} data opts]
    if {$failed && [lrange [dict get $opts -errorcode] 0 2] eq {DEMLAB LOOKUP ELEMENT}} {
        # A selected element is gone (removed, or a new scene): keep those that remain.
        set ::demlab::viewer::selection [::demlab::viewer selection]
        set failed [catch {::demlab::viewer frame {*}[Options]} data]
    }
    if {$failed} {
        set ::demlab::viewer::status $data
        $picture blank
        return
    }
    $picture put $data -format ppm
    incr ::demlab::viewer::frames
}

# Redraws everything the window shows: picture, selected element, plot, status.
proc ::demlab::viewer::Refresh {} {
    variable w
    if {![Shown]} return
    set ::demlab::viewer::status ""
    if {![catch {::demlab::sim info} info] && [dict get $info dimension] != $::demlab::viewer::dim} {
        # A new scene of the other dimension: the camera kept is of no use to it.
        set ::demlab::viewer::dim [dict get $info dimension]
        set ::demlab::viewer::camera {}
    }
    Draw
    Info
    Plot
    if {$::demlab::viewer::status eq "" && ![catch {::demlab::sim info} info]} {
        set ::demlab::viewer::status [format "t = %.6g s   step %d   %d elements" \
            [dict get $info time] [dict get $info steps] [dict get $info elements]]
    }
    set ::demlab::viewer::seen [::demlab::viewer changes]
}

# Called from inside a run (the command layer limits it to the frame rate): redraws the
# picture and lets Tk handle its events. While it does, commands that change the scene are
# refused, so Play, Step and the side panes wait for the run's end.
proc ::demlab::viewer::Tick {} {
    variable w
    variable inRun
    if {![Shown] || $inRun} return
    set inRun 1
    try {
        Draw
        update
    } finally {
        set inRun 0
    }
}

# Every fifth of a second while the window is open: a redraw when a command changed the scene.
proc ::demlab::viewer::Poll {} {
    variable w
    if {![Shown]} return
    if {!$::demlab::viewer::inRun && [::demlab::viewer changes] != $::demlab::viewer::seen} {
        Refresh
    }
    set ::demlab::viewer::poll [after 200 ::demlab::viewer::Poll]
}

# Play: runs the scene in chunks from the event loop, each about a frame's time long.
proc ::demlab::viewer::Play {} {
    variable playing
    if {$playing} return
    set playing 1
    after idle ::demlab::viewer::PlayChunk
}

proc ::demlab::viewer::PlayChunk {} {
    variable playing
    variable chunk
    if {!$playing || ![Shown]} {set playing 0; return}
    if {$::demlab::viewer::inRun} {after 100 ::demlab::viewer::PlayChunk; return}
    set t0 [clock microseconds]
    if {[catch {::demlab::sim run -steps $chunk -quiet} msg opts]} {
        if {[lrange [dict get $opts -errorcode] 0 2] eq {DEMLAB STATE RUNNING}} {
            after 100 ::demlab::viewer::PlayChunk
            return
        }
        set playing 0
        Refresh
        if {[lrange [dict get $opts -errorcode] 0 1] ne {DEMLAB INTERRUPTED}} {
            set ::demlab::viewer::status $msg
        }
        return
    }
    # Chunks grow or shrink by halves towards a frame's wall-clock time.
    set ms [expr {([clock microseconds] - $t0) / 1000.0}]
    set frame [expr {1000.0 / $::demlab::viewer::fps}]
    if {$ms < $frame / 2 && $chunk < 1000000} {
        set chunk [expr {$chunk * 2}]
    } elseif {$ms > 2 * $frame && $chunk > 1} {
        set chunk [expr {$chunk / 2}]
    }
    Refresh
    after 1 ::demlab::viewer::PlayChunk
}

# Pause: stops playing, and a run in progress (a console's sim run too) at its next step.
proc ::demlab::viewer::Pause {} {
    set ::demlab::viewer::playing 0
    if {$::demlab::viewer::inRun} {::demlab::viewer stop}
}

proc ::demlab::viewer::Step {} {
    if {$::demlab::viewer::inRun || $::demlab::viewer::playing} return
    if {[catch {::demlab::sim step} msg]} {set ::demlab::viewer::status $msg; return}
    Refresh
}

# Sets the camera (a dict as kept here, or {} for the automatic framing) and redraws.
proc ::demlab::viewer::SetCamera {c} {
    set ::demlab::viewer::camera $c
    Draw
}

# Returns the camera, the automatic one resolved when none is set.
proc ::demlab::viewer::Camera {} {
    variable camera
    if {[dict size $camera] == 0} {
        set camera [::demlab::viewer camera {*}[Options]]
    }
    return $camera
}

proc ::demlab::viewer::Press {x y state button} {
    # Button 2, or Shift with button 1, pans; button 1 orbits in 3D and pans in 2D.
    set mode [expr {$button == 2 || ($state & 1) ? "pan" : "orbit"}]
    if {[Dim] == 2} {set mode pan}
    set ::demlab::viewer::drag [list $x $y $x $y $mode 0]
}

proc ::demlab::viewer::Motion {x y} {
    variable drag
    if {$drag eq ""} return
    lassign $drag x0 y0 px py mode moved
    if {!$moved && abs($x - $x0) + abs($y - $y0) < 3} return
    set drag [list $x0 $y0 $x $y $mode 1]
    if {$mode eq "orbit"} {
        Orbit [expr {$x - $px}] [expr {$y - $py}]
    } else {
        Pan [expr {$x - $px}] [expr {$y - $py}]
    }
}

proc ::demlab::viewer::Release {x y state} {
    variable drag
    if {$drag eq ""} return
    lassign $drag x0 y0 px py mode moved
    set drag ""
    if {$moved} return
    # A click: the element under the pointer; Control adds it to the selection.
    if {[catch {::demlab::viewer pick $x $y {*}[Options]} id]} {
        set ::demlab::viewer::status $id
        return
    }
    if {$id eq ""} {
        if {!($state & 4)} {Select {}}
        return
    }
    Select [list $id] [expr {($state & 4) != 0}]
}

# Selects ids (added to the selection when add), and shows the first one's state.
proc ::demlab::viewer::Select {ids {add 0}} {
    variable selection
    if {$add} {
        foreach id $ids {if {$id ni $selection} {lappend selection $id}}
    } else {
        set selection $ids
    }
    Info
    Draw
}

# Turns the camera about the point looked at: a drag of dx pixels turns it by -dx * pi / height
# about its up direction, one of dy pixels by -dy * pi / height about its right direction, so a
# drag across the picture's height is half a turn.
proc ::demlab::viewer::Orbit {dx dy} {
    set c [Camera]
    set k [expr {acos(-1) / $::demlab::viewer::height}]
    set look [dict get $c lookat]
    set up [dict get $c up]
    set off [Sub [dict get $c position] $look]
    set off [Rotate $off $up [expr {-$dx * $k}]]
    set right [Unit [Cross [Scale $off -1] $up]]
    set off [Rotate $off $right [expr {-$dy * $k}]]
    set up [Unit [Rotate $up $right [expr {-$dy * $k}]]]
    dict set c position [Add $look $off]
    dict set c up $up
    SetCamera $c
}

# Moves the camera and the point it looks at with the pointer, at the scale of that point.
proc ::demlab::viewer::Pan {dx dy} {
    set c [Camera]
    set look [dict get $c lookat]
    set h $::demlab::viewer::height
    if {[Dim] == 2} {
        set s [expr {[dict get $c viewheight] / $h}]
        lassign $look x y
        dict set c lookat [list [expr {$x - $dx * $s}] [expr {$y + $dy * $s}] 0]
        SetCamera $c
        return
    }
    set off [Sub [dict get $c position] $look]
    if {[dict get $c orthographic]} {
        set s [expr {[dict get $c viewheight] / $h}]
    } else {
        set s [expr {2 * [Norm $off] * tan([dict get $c fov] * acos(-1) / 360) / $h}]
    }
    set up [dict get $c up]
    set right [Unit [Cross [Scale $off -1] $up]]
    set move [Add [Scale $right [expr {-$dx * $s}]] [Scale $up [expr {$dy * $s}]]]
    dict set c lookat [Add $look $move]
    dict set c position [Add [dict get $c position] $move]
    SetCamera $c
}

# Zooms in (n > 0) or out by 10% a notch: the camera nearer the point looked at, or the
# orthographic height smaller.
proc ::demlab::viewer::Zoom {n} {
    set c [Camera]
    set f [expr {0.9 ** $n}]
    dict set c viewheight [expr {[dict get $c viewheight] * $f}]
    if {[Dim] == 3 && ![dict get $c orthographic]} {
        set look [dict get $c lookat]
        dict set c position [Add $look [Scale [Sub [dict get $c position] $look] $f]]
    }
    SetCamera $c
}

# Shows the state of the first selected element and its contacts.
proc ::demlab::viewer::Info {} {
    variable w
    variable selection
    if {![Shown] || $::demlab::viewer::inRun} return
    set t $w.side.info
    $t configure -state normal
    $t delete 1.0 end
    set id [lindex $selection 0]
    if {$id ne "" && ![catch {::demlab::element get $id} d]} {
        foreach key {id name material tags radius mass position velocity angularvelocity
                     force torque} {
            if {![dict exists $d $key]} continue
            set v [dict get $d $key]
            if {[llength $v] > 1 && [string is double -strict [lindex $v 0]]} {
                set v [lmap x $v {format %.4g $x}]
            } elseif {[string is double -strict $v] && ![string is integer -strict $v]} {
                set v [format %.4g $v]
            }
            $t insert end [format "%-16s %s\n" $key $v]
        }
        if {![catch {::demlab::query contacts -element $id} cs]} {
            set with {}
            foreach c $cs {
                lappend with [expr {[dict get $c a] != $id ? [dict get $c a] :
                    [dict get $c b] ne "" ? [dict get $c b] : "wall [dict get $c wall]"}]
            }
            $t insert end [format "%-16s %d: %s\n" contacts [llength $cs] [lrange $with 0 7]]
        }
        if {[llength $selection] > 1} {
            $t insert end "\n[llength $selection] selected: [lrange $selection 0 11]\n"
        }
    } elseif {$id ne ""} {
        $t insert end "element $id is gone"
    } else {
        $t insert end "Click an element to see its state.\n(viewer selection at the console)"
    }
    $t configure -state disabled
}

# The series the plot can show: "ID QUANTITY" for each column of each series output.
proc ::demlab::viewer::SeriesChoices {} {
    set l {}
    if {![catch {::demlab::series list} all]} {
        foreach s $all {
            foreach q [dict get $s quantities] {
                if {[llength $q] > 1} {set q [lindex $q 0]}
                if {$q ni {time step}} {lappend l "[dict get $s id] $q"}
            }
        }
    }
    $::demlab::viewer::w.side.series configure -values $l
}

# Plots the chosen series column against time (or row number) on the side canvas.
proc ::demlab::viewer::Plot {} {
    variable w
    variable plotted
    if {![Shown] || $::demlab::viewer::inRun} return
    set cv $w.side.plot
    $cv delete all
    lassign $plotted id q
    if {$id eq "" || [catch {::demlab::series get $id} cols] || ![dict exists $cols $q]} return
    set ys [dict get $cols $q]
    set xs [expr {[dict exists $cols time] ? [dict get $cols time] : [lsearch -all $ys *]}]
    set pts {}
    foreach x $xs y $ys {
        if {[string is double -strict $x] && [string is double -strict $y] &&
            $x == $x && $y == $y} {lappend pts $x $y}
    }
    if {[llength $pts] < 4} return
    set x0 [lindex $pts 0]; set x1 $x0; set y0 [lindex $pts 1]; set y1 $y0
    foreach {x y} $pts {
        set x0 [expr {min($x0, $x)}]; set x1 [expr {max($x1, $x)}]
        set y0 [expr {min($y0, $y)}]; set y1 [expr {max($y1, $y)}]
    }
    if {$x1 == $x0} {set x1 [expr {$x0 + 1}]}
    if {$y1 == $y0} {set y1 [expr {$y0 + 1}]}
    set W [winfo reqwidth $cv]; set H [winfo reqheight $cv]
    set l 46; set r 8; set top 8; set b 22
    set line {}
    foreach {x y} $pts {
        lappend line [expr {$l + ($x - $x0) / ($x1 - $x0) * ($W - $l - $r)}] \
            [expr {$H - $b - ($y - $y0) / ($y1 - $y0) * ($H - $top - $b)}]
    }
    $cv create rectangle $l $top [expr {$W - $r}] [expr {$H - $b}] -outline grey60
    $cv create line {*}$line -fill #1f5fa8 -width 1.5
    $cv create text 2 $top -anchor nw -text [format %.3g $y1] -font TkSmallCaptionFont
    $cv create text 2 [expr {$H - $b}] -anchor sw -text [format %.3g $y0] -font TkSmallCaptionFont
    $cv create text $l [expr {$H - 2}] -anchor sw -text [format %.3g $x0] -font TkSmallCaptionFont
    $cv create text [expr {$W - $r}] [expr {$H - 2}] -anchor se -font TkSmallCaptionFont \
        -text "[format %.3g $x1] [expr {[dict exists $cols time] ? {s} : {row}}]"
    $cv create text [expr {$W / 2}] $top -anchor n -text $q -font TkSmallCaptionFont
}

# Vectors of three numbers.
proc ::demlab::viewer::Add {a b} {lmap x $a y $b {expr {$x + $y}}}
proc ::demlab::viewer::Sub {a b} {lmap x $a y $b {expr {$x - $y}}}
proc ::demlab::viewer::Scale {a s} {lmap x $a {expr {$x * $s}}}
proc ::demlab::viewer::Dot {a b} {
    set s 0.0
    foreach x $a y $b {set s [expr {$s + $x * $y}]}
    return $s
}
proc ::demlab::viewer::Norm {a} {expr {sqrt([Dot $a $a])}}
proc ::demlab::viewer::Unit {a} {Scale $a [expr {1.0 / [Norm $a]}]}
proc ::demlab::viewer::Cross {a b} {
    lassign $a ax ay az
    lassign $b bx by bz
    list [expr {$ay * $bz - $az * $by}] [expr {$az * $bx - $ax * $bz}] \
        [expr {$ax * $by - $ay * $bx}]
}
# Returns v turned by angle (radians) about the unit axis k (Rodrigues).
proc ::demlab::viewer::Rotate {v k angle} {
    set c [expr {cos($angle)}]
    set s [expr {sin($angle)}]
    set kv [Dot $k $v]
    Add [Add [Scale $v $c] [Scale [Cross $k $v] $s]] [Scale $k [expr {$kv * (1 - $c)}]]
}
