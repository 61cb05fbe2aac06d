# demlab's Tcl-level library: procedures written in Tcl over the commands that the C++ layer
# defines. It is compiled into the extension and the executable (so the two always agree) and
# also installed beside pkgIndex.tcl for reading.

namespace eval ::demlab {
    namespace export settle each report
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
