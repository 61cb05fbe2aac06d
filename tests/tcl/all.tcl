# Runs every tests/tcl/*.test file in one interpreter, through the demlab executable
# (`demlab all.tcl`) or, with -package, through `package require demlab` in a plain tclsh.
# Exits 1 if any test failed, so ctest sees failures.
package require Tcl 8.6
package require tcltest 2.5
if {[lsearch -exact $argv -package] >= 0} {
    set argv [lsearch -all -inline -not -exact $argv -package]
}
package require demlab
set ::demlab_failed 0
proc tcltest::cleanupTestsHook {} {
    incr ::demlab_failed $tcltest::numTests(Failed)
}
tcltest::configure -testdir [file dirname [file normalize [info script]]] -singleproc 1
tcltest::configure {*}$argv
tcltest::runAllTests
exit [expr {$::demlab_failed > 0}]
