# compare_runs.tcl serial.txt ranks.txt np ?ledger?: compares what falling_bed.tcl printed alone
# and on np ranks. One rank must give the serial run's bits. On more, the order in which an element's
# contact forces are added differs (its own rank's pairs, then the ghosts' forces from the
# others), so reals agree to round-off grown over the run: positions within 1e-10 m (1e-7 of a
# radius), velocities within 1e-7 m/s, energies within 1e-7 of their largest component, forces
# on walls within 1e-6 (a sum of stiff contacts' forces: 1e-11 m apart in the grains touching
# a moving wall made 3 ranks' force on it 6e-7 of it apart); counts exactly. ledger (default 1e-7) replaces that 1e-7 for the energies and
# bounds the difference of the energy residuals (a fraction of the energy scale already):
# checkpoint_bed.tcl's runs loaded on other ranks search at another step than the saving run,
# and a search drops each contact's damper loss still to book (sim/history_store.hpp), about
# 1e-6 of the damping loss there.
lassign $argv serialFile ranksFile np ledger
if {$ledger eq ""} { set ledger 1e-7 }
proc readRun {file} {
    set f [open $file]
    set d {}
    foreach line [split [read $f] \n] {
        set line [string trimright $line \r]
        if {$line ne ""} { dict set d [lindex $line 0] [lrange $line 1 end] }
    }
    close $f
    return $d
}
set serial [readRun $serialFile]
set ranks [readRun $ranksFile]
set failures {}
set worst {}
if {[dict keys $serial] ne [dict keys $ranks]} {
    lappend failures "keys differ: [dict keys $serial] / [dict keys $ranks]"
}
dict for {key a} $serial {
    if {![dict exists $ranks $key]} continue
    set b [dict get $ranks $key]
    if {$np == 1 || [regexp {^(steps|time|rebuilds|elements|walls|contacts[23]?|count|list|radii|coordination|contactlist|addedid|addedname|removed(tag|named)?|tagcount|taglist|tagids|tags|tagged|againid|nextid|wallsleft|seriesplot|blocked|series2?(time|step|elements|contacts|file))$} $key]} {
        if {$a ne $b} { lappend failures "$key: $a alone, $b on $np ranks" }
        continue
    }
    switch -glob $key {
        position* - bounds { set tol 1e-10 }
        velocity* { set tol 1e-7 }
        residual* { set tol $ledger }
        floorforce - sideforce - movedwall - lidforce - series*wall_*_f* {
            set largest 0
            foreach x $a { set largest [expr {max($largest, abs($x))}] }
            set tol [expr {max(1e-6, $ledger) * $largest + 1e-300}]
        }
        default {
            set largest 0
            foreach x $a { set largest [expr {max($largest, abs($x))}] }
            set tol [expr {$ledger * $largest + 1e-300}]
        }
    }
    set diff 0
    foreach x $a y $b { set diff [expr {max($diff, abs($x - $y))}] }
    if {!($diff <= $tol)} { lappend failures "$key: $a alone, $b on $np ranks (|diff| $diff > $tol)" }
    lappend worst "$key [format %.1e $diff]"
}
if {[llength $failures]} {
    puts stderr [join $failures \n]
    exit 1
}
puts "np $np: [dict size $serial] values agree[expr {$np == 1 ? " bit for bit" : ""}]"
if {[llength $worst]} { puts "largest differences: [join $worst {, }]" }
