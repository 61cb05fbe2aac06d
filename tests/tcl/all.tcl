# Runs every tests/tcl/*.test file in one interpreter, through the demlab executable
# (`demlab all.tcl`) or, with -package, through `package require demlab` in a plain tclsh.
# Exits 1 if any test failed, so ctest sees failures.
package require Tcl 8.6
package require tcltest 2.5
if {[lsearch -exact $argv -package] >= 0} {
    set argv [lsearch -all -inline -not -exact $argv -package]
}
package require demlab
# The executable has the commands in the global namespace; a plain tclsh imports them.
if {[info commands ::sim] eq ""} {namespace import ::demlab::*}
set ::demlab_failed 0
proc tcltest::cleanupTestsHook {} {
    incr ::demlab_failed $tcltest::numTests(Failed)
}
# Files the tests make go to a fresh folder under the system's temporary directory.
set tmp [file join [expr {[info exists env(TMPDIR)] ? $env(TMPDIR) : "/tmp"}] demlab-tcltest-[pid]]
file mkdir $tmp
tcltest::configure -testdir [file dirname [file normalize [info script]]] -singleproc 1 -tmpdir $tmp
tcltest::configure {*}$argv
tcltest::runAllTests
file delete -force $tmp
exit [expr {$::demlab_failed > 0}]
