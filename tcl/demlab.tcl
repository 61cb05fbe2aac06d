# demlab's Tcl-level library: procedures written in Tcl over the commands that the C++ layer
# defines. It is compiled into the extension and the executable (so the two always agree) and
# also installed beside pkgIndex.tcl for reading.

namespace eval ::demlab {
    namespace export settle each report sample levelset
}

# demlab::settle ?-energy E? ?-chunk N? ?-maxsteps N?
# Runs the scene in chunks of -chunk steps (one at least) until its kinetic energy (translational plus
# rotational, J) falls below -energy, or -maxsteps have been run. Returns a dict: steps (run by
# this call), kinetic (at the end), settled (1 if the threshold was reached). Errors of the
# underlying sim run (Ctrl-C among them) pass through.
proc ::demlab::settle {args} {
    array set opt {-energy 1e-9 -chunk 500 -maxsteps 1000000}
    if {[llength $args] % 2} {
        return -code error -errorcode {DEMLAB ARGS} \
            {wrong # args: should be "demlab::settle ?-energy E? ?-chunk N? ?-maxsteps N?"}
    }
    foreach {k v} $args {
        set full [lsearch -inline -all -glob {-energy -chunk -maxsteps} $k*]
        if {[llength $full] != 1} {
            return -code error -errorcode {DEMLAB OPTION} \
                "bad option \"$k\": must be -energy, -chunk, or -maxsteps"
        }
        set name [string range [lindex $full 0] 1 end]
        if {$name eq "energy"} {
            if {![string is double -strict $v] || !($v > 0) || $v == Inf} {
                return -code error -errorcode {DEMLAB VALUE ENERGY} \
                    "bad energy \"$v\": must be a positive finite number"
            }
        } elseif {![string is wideinteger -strict $v] || $v <= 0} {
            # Whole steps only: a fractional chunk would run no steps and loop for ever.
            return -code error -errorcode [list DEMLAB VALUE [string toupper $name]] \
                "bad $name \"$v\": must be a positive integer"
        }
        set opt([lindex $full 0]) $v
    }
    # At least one chunk: a bed at rest before its first step is not settled under gravity.
    set done 0
    set kinetic Inf
    while {$kinetic >= $opt(-energy) && $done < $opt(-maxsteps)} {
        set n [expr {min($opt(-chunk), $opt(-maxsteps) - $done)}]
        sim run -steps $n -quiet
        incr done $n
        set kinetic [demlab::KineticEnergy]
    }
    return [dict create steps $done kinetic $kinetic settled [expr {$kinetic < $opt(-energy)}]]
}

# demlab::levelset vars expression -box {lo hi} -spacing h
# Returns the -params of the level-set shape where expression, a function of the coordinates
# named by vars ({x y z} in 3D, {x y} in 2D), is negative: it is sampled on the grid of spacing
# h over the box from corner lo to corner hi, which must hold the body with the function
# positive on its border, and `element levelset -values` re-distances it. The expression runs
# in a procedure of its own (as a lambda): it sees only its variables and globals.
proc ::demlab::levelset {vars expression args} {
    set usage {wrong # args: should be "demlab::levelset vars expression -box {lo hi} -spacing h"}
    if {[llength $args] != 4} {return -code error -errorcode {DEMLAB ARGS} $usage}
    set dim [dict get [sim info] dimension]
    if {[llength $vars] != $dim} {
        return -code error -errorcode {DEMLAB VALUE VARS} \
            "bad vars \"$vars\": must name $dim coordinates"
    }
    foreach {k v} $args {
        switch -- $k {
            -box {set box $v}
            -spacing {set h $v}
            default {
                return -code error -errorcode {DEMLAB OPTION} \
                    "bad option \"$k\": must be -box or -spacing"
            }
        }
    }
    if {![info exists box] || ![info exists h]} {return -code error -errorcode {DEMLAB ARGS} $usage}
    if {![string is double -strict $h] || !($h > 0) || $h == Inf} {
        return -code error -errorcode {DEMLAB VALUE SPACING} "bad spacing \"$h\": must be a positive length"
    }
    if {[catch {llength $box} n] || $n != 2 || [llength [lindex $box 0]] != $dim
            || [llength [lindex $box 1]] != $dim} {
        return -code error -errorcode {DEMLAB VALUE BOX} \
            "bad box \"$box\": must be {lo hi}, two corners of $dim coordinates"
    }
    lassign $box lo hi
    set dims {}
    foreach a $lo b $hi {
        if {![string is double -strict $a] || ![string is double -strict $b] || !($b > $a)} {
            return -code error -errorcode {DEMLAB VALUE BOX} \
                "bad box \"$box\": each corner's coordinates must be numbers, lo < hi"
        }
        set count [expr {int(ceil(($b - $a) / $h)) + 1}]
        if {$count > 400} {
            return -code error -errorcode {DEMLAB VALUE SPACING} \
                "bad spacing \"$h\": the box needs $count nodes along an axis, more than 400"
        }
        lappend dims $count
    }
    set f [list $vars [list expr $expression]]
    set values {}
    set x0 [lindex $lo 0]; set y0 [lindex $lo 1]; set z0 [lindex $lo 2]
    lassign $dims nx ny nz
    if {$dim == 2} {set nz 1}
    for {set k 0} {$k < $nz} {incr k} {
        for {set j 0} {$j < $ny} {incr j} {
            for {set i 0} {$i < $nx} {incr i} {
                set point [list [expr {$x0 + $i * $h}] [expr {$y0 + $j * $h}]]
                if {$dim == 3} {lappend point [expr {$z0 + $k * $h}]}
                if {[catch {apply $f {*}$point} v]} {
                    return -code error -errorcode {DEMLAB VALUE EXPRESSION} \
                        "bad expression: at ($point) it failed: $v"
                }
                lappend values $v
            }
        }
    }
    element levelset -values $values -dims $dims -origin $lo -spacing $h
}

proc ::demlab::KineticEnergy {} {
    set e [query energy]
    expr {[dict get $e kinetic] + [dict get $e rotational]}
}

# demlab::each varName ?-tag tag? body
# Runs body once per element id (of the tag, if given), with varName set to the id, in the
# order of element list. break and continue work as in foreach. Returns the empty string.
proc ::demlab::each {args} {
    set varName [lindex $args 0]
    set args [lrange $args 1 end]
    if {[llength $args] == 1} {
        set ids [element list]
    } elseif {[llength $args] == 3 && [lindex $args 0] eq "-tag"} {
        set ids [element list -tag [lindex $args 1]]
    } else {
        return -code error -errorcode {DEMLAB ARGS} \
            {wrong # args: should be "demlab::each varName ?-tag tag? body"}
    }
    upvar 1 $varName id
    set body [lindex $args end]
    foreach id $ids {
        set code [catch {uplevel 1 $body} result options]
        switch -- $code {
            0 - 4 {}
            3 {break}
            default {return -options $options $result}
        }
    }
    return
}

# demlab::report dict
# Returns the text of a run report dict (what sim run prints) for logging from scripts.
proc ::demlab::report {args} {
    if {[llength $args] != 1} {
        return -code error -errorcode {DEMLAB ARGS} {wrong # args: should be "demlab::report dict"}
    }
    set r [lindex $args 0]
    set keys {steps simulated time wall residual modules contacts rebuilds}
    if {[catch {dict size $r}] || [catch {dict size [dict get $r modules]}] ||
            [llength [lmap k $keys {expr {[dict exists $r $k] ? [continue] : $k}}]]} {
        return -code error -errorcode {DEMLAB VALUE REPORT} \
            "bad report \"[string range $r 0 60]\": must be a dict returned by sim run\
            (with keys [join $keys {, }])"
    }
    set s [format "run: %d steps, %.6g s simulated (t = %.6g s), wall %.3g s, energy residual %.3g" \
        [dict get $r steps] [dict get $r simulated] [dict get $r time] [dict get $r wall] \
        [dict get $r residual]]
    set parts {}
    dict for {m sec} [dict get $r modules] {lappend parts [format "%s %.3g us" $m [expr {$sec * 1e6}]]}
    if {[llength $parts]} {append s "\n  per step: [join $parts {, }]"}
    append s [format "\n  contacts %d, neighbour searches %d" \
        [dict get $r contacts] [dict get $r rebuilds]]
    return $s
}

# demlab::sample -region REGION -radius DIST -model MODEL ?-material M? ?-wallmaterial W?
#     ?-seed N? ?-start F? ?-overlap X? ?-iterations N? ?-gap G? ?-tag T? ?-steps N?
#     ?-keepwalls 0|1?
# Makes a bonded sample after Potyondy and Cundall's genesis: places elements of the size
# distribution DIST (as pack random takes it) at random in REGION at solid fraction -start
# (default 0.5 in 2D, 0.3 in 3D), holds them by walls of -wallmaterial (default: the
# elements' material) on the region's boundary (planes for a
# box, a drum for a disc in 2D or a cylinder in 3D, the cylinder closed by two planes) and
# grows every radius (element resize) in steps of 1 % (in the logarithm of the factor), each
# followed by sim relax -overlap X -iterations N (defaults 1e-5 and 300): the geometric
# separation of the overlaps, without dynamics and so without kinetic energy to damp. When the
# separation fails the step is undone and the steps made ten times shorter, down to 1e-4: the
# packing is then one at the edge of jamming whose overlaps are below X times the smaller
# radius, which bounds the stress locked into it. With the material's friction off (and its
# restitution 0.05) it runs -steps steps (default 1000) from rest, bonds every pair within -gap
# (default 1 % of the mean radius) with MODEL, gives the friction and restitution back, removes
# the walls (unless -keepwalls 1) and lets the bonded sample relax -steps steps. The stresses
# reported are Love-Weber mean stresses over the region's volume, compression positive (per
# unit thickness in 2D).
# Returns a dict: elements, bonds (their number), fraction (the region's solid fraction when
# bonded), stress (the mean stress of the forces between elements when bonded, Pa), lockedin
# (the mean stress of the contacts alone after the walls went and the sample relaxed, Pa: the
# compression the sample keeps, which the bonds' tension balances, so that in a sample at rest
# without walls the two add up to about zero), factor (the radii's growth), steps (run by this call), walls
# (the ids left), tag. Changes the scene: adds the elements (tagged -tag, default sample), the
# bonds and, with -keepwalls 1, the walls; runs it. Errors: DEMLAB ARGS, DEMLAB OPTION, DEMLAB
# VALUE <OPTION>, DEMLAB LOOKUP BONDMODEL, and those of the commands it calls (nothing is added
# when pack random fails).
proc ::demlab::sample {args} {
    set usage {demlab::sample -region REGION -radius DIST -model MODEL ?-option value ...?}
    set d [sim dimension]
    array set opt [list -material {} -wallmaterial {} -seed 1 -start [expr {$d == 2 ? 0.5 : 0.3}] -gap {} \
        -tag sample -steps 1000 -overlap 1e-5 -iterations 300 -keepwalls 0]
    set required {-region -radius -model}
    if {[llength $args] % 2} {
        return -code error -errorcode {DEMLAB ARGS} "wrong # args: should be \"$usage\""
    }
    set known [lsort [concat $required [array names opt]]]
    foreach {k v} $args {
        if {$k ni $known} {
            return -code error -errorcode {DEMLAB OPTION} \
                "bad option \"$k\": must be [join [lrange $known 0 end-1] {, }] or [lindex $known end]"
        }
        set opt($k) $v
    }
    foreach k $required {
        if {![info exists opt($k)]} {
            return -code error -errorcode {DEMLAB ARGS} \
                "missing required option $k: should be \"$usage\""
        }
    }
    foreach {k test why} {
        -start {$v > 0 && $v < 0.9} "a fraction in (0, 0.9)"
        -overlap {$v > 0 && $v <= 1} "a fraction in (0, 1]"
        -iterations {$v == int($v) && $v >= 1} "a positive integer"
        -steps {$v == int($v) && $v >= 1} "a positive integer"
        -gap {$v >= 0 && $v < Inf} "a non-negative finite number"
    } {
        set v $opt($k)
        if {$k eq "-gap" && $v eq {}} continue
        if {![string is double -strict $v] || ![expr $test]} {
            set name [string range $k 1 end]
            return -code error -errorcode [list DEMLAB VALUE [string toupper $name]] \
                "bad $name \"$v\": must be $why"
        }
    }
    if {$opt(-model) ni [lmap m [bond models] {dict get $m name}]} {
        return -code error -errorcode {DEMLAB LOOKUP BONDMODEL} "no bond model named \"$opt(-model)\""
    }
    if {$d == 3 && [lindex $opt(-region) 0] eq "sphere"} {
        return -code error -errorcode {DEMLAB VALUE REGION} \
            "bad region \"$opt(-region)\": a 3D sample is a box or a cylinder"
    }
    set material $opt(-material)
    if {$material eq {}} {set material [lindex [material list] 0]}
    set region $opt(-region)
    set tag $opt(-tag)
    set ids [pack random -region $region -radius $opt(-radius) -fraction $opt(-start) \
        -seed $opt(-seed) -material $material -tags [list $tag]]
    set wallMaterial [expr {$opt(-wallmaterial) eq {} ? $material : $opt(-wallmaterial)}]
    set walls [demlab::RegionWalls $region $d $wallMaterial]
    set volume [demlab::RegionVolume $region $d]
    set friction [material get $material -friction]
    set restitution [material get $material -restitution]
    # Frictionless and nearly critically damped contacts: a dense pack at rest. The watchdog's
    # energy check off until the end: the scene's energy scale is next to zero, at rest, and
    # round-off alone exceeds its fraction of it.
    material set $material -friction 0 -restitution 0.05
    set energyCheck [dict get [module watchdog] energy]
    module watchdog -energy 0
    # Radius expansion without dynamics (no kinetic energy to damp): the radii grow in steps,
    # each followed by sim relax, until it can no longer separate the overlaps (the packing has
    # jammed); the last step is then undone and the steps made ten times shorter, down to 1e-4.
    set s 0.0
    set inc 0.01
    set relaxed $opt(-overlap)
    while {$inc >= 1e-4} {
        element resize -tag $tag -factor [expr {exp($inc)}]
        set r [sim relax -overlap $relaxed -iterations $opt(-iterations)]
        if {[dict get $r after] <= $relaxed} {
            set s [expr {$s + $inc}]
            continue
        }
        element resize -tag $tag -factor [expr {exp(-$inc)}]
        sim relax -overlap $relaxed -iterations $opt(-iterations)
        set inc [expr {$inc / 10}]
    }
    # The dynamics from rest settle what the separation left.
    set steps $opt(-steps)
    sim run -steps $steps -quiet -progress 0
    set p [demlab::MeanStress $tag $volume]
    set fraction [dict get [query packing -region $region -tag $tag] fraction]
    set gap $opt(-gap)
    if {$gap eq {}} {
        set radii [element array radius -tag $tag]
        set gap [expr {0.01 * [tcl::mathop::+ {*}$radii] / [llength $radii]}]
    }
    set bonds [llength [bond add -model $opt(-model) -gap $gap -tag $tag]]
    material set $material -friction $friction -restitution $restitution
    if {!$opt(-keepwalls)} {
        wall remove {*}$walls
        set walls {}
    }
    sim run -steps $opt(-steps) -quiet -progress 0
    incr steps $opt(-steps)
    module watchdog -energy $energyCheck
    dict create elements [llength $ids] bonds $bonds fraction $fraction stress $p \
        lockedin [demlab::MeanStress $tag $volume contacts] factor [expr {exp($s)}] \
        steps $steps walls $walls tag $tag
}

# Returns the mean static stress (compression positive) of the elements carrying tag over
# volume (an area in 2D).
proc ::demlab::MeanStress {tag volume {part static}} {
    dict get [query stress -tag $tag -volume $volume -part $part] pressure
}

# Returns the volume (area in 2D) of a pack region {box lo hi}, {sphere centre r} (a disc in
# 2D) or {cylinder centre axis r halflength}.
proc ::demlab::RegionVolume {region d} {
    switch -- [lindex $region 0] {
        box {
            set v 1.0
            foreach a [lrange [lindex $region 1] 0 $d-1] b [lrange [lindex $region 2] 0 $d-1] {
                set v [expr {$v * ($b - $a)}]
            }
            return $v
        }
        sphere {
            set r [lindex $region 2]
            return [expr {$d == 2 ? acos(-1) * $r * $r : 4.0 / 3 * acos(-1) * $r ** 3}]
        }
        cylinder {
            lassign $region - - - r h
            return [expr {acos(-1) * $r * $r * 2 * $h}]
        }
    }
}

# Adds the walls that hold a pack region's elements in: a plane on each face of a box, a drum
# around a disc (2D) or a cylinder (3D, with a plane on each end). Returns their ids; throws
# nothing (the caller refuses a sphere in 3D: no wall holds one).
proc ::demlab::RegionWalls {region d material} {
    set walls {}
    switch -- [lindex $region 0] {
        box {
            lassign $region - lo hi
            for {set k 0} {$k < $d} {incr k} {
                set n [lrepeat $d 0]
                lappend walls [wall add plane -normal [lreplace $n $k $k 1] -point $lo -material $material]
                lappend walls [wall add plane -normal [lreplace $n $k $k -1] -point $hi -material $material]
            }
        }
        sphere {
            lassign $region - c r
            lappend walls [wall add drum -radius $r -point $c -material $material]
        }
        cylinder {
            lassign $region - c axis r h
            set len [expr {sqrt([tcl::mathop::+ {*}[lmap a $axis {expr {$a * $a}}]])}]
            set u [lmap a $axis {expr {$a / $len}}]
            lappend walls [wall add drum -radius $r -axis $u -halflength $h -point $c -material $material]
            foreach sign {1 -1} {
                set p [lmap x $c a $u {expr {$x - $sign * $h * $a}}]
                lappend walls [wall add plane -normal [lmap a $u {expr {$sign * $a}}] -point $p -material $material]
            }
        }
    }
    return $walls
}
