# One rank gets Ctrl-C alone (SIGINT to its own process) during a long run while the others
# step on: every rank must stop at the same step boundary with DEMLAB INTERRUPTED, none left
# waiting in an exchange, and the scene must run on. Each rank writes what it saw to
# <dir>/rank<R>.txt: {code errorcode {step N}}, then {next code} of a short run after it.
set dir [lindex $argv 0]
source [file join [file dirname [info script]] bed_scene.tcl]
makeBed
sim run -steps 10 -quiet
set me [dict get [sim ranks] rank]
if {$me == [dict get [sim ranks] ranks] - 1} {
    exec sh -c "sleep 0.5; kill -INT [pid]" &
}
set code [catch {sim run -steps 100000000 -quiet} msg opts]
set f [open [file join $dir rank$me.txt] w]
puts $f [list $code [dict get $opts -errorcode] [lindex [regexp -inline {step [0-9]+} $msg] 0]]
puts $f [list next [catch {sim run -steps 10 -quiet}]]
close $f
