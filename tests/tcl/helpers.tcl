# Shared by the test files: scene builders and the check that a failing call changes nothing.

# Starts a new scene of dimension dim with one material, glass.
proc newScene {{dim 3}} {
    sim new -dim $dim
    material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5
}

# Evaluates script in the caller, which must fail. Returns {errorcode message unchanged},
# where the last word is "unchanged" when the scene's digest is the same before and after the
# call, "CHANGED" otherwise; or "no error: <result>" when the script succeeded.
proc fails {script} {
    set before [sim digest]
    if {![catch {uplevel 1 $script} msg opts]} {
        return "no error: $msg"
    }
    set after [sim digest]
    list [dict get $opts -errorcode] $msg [expr {$before eq $after ? "unchanged" : "CHANGED"}]
}

# Returns 1 if the two lists of numbers agree within tol, component by component.
proc near {a b {tol 1e-12}} {
    if {[llength $a] != [llength $b]} {return 0}
    foreach x $a y $b {
        if {abs($x - $y) > $tol} {return 0}
    }
    return 1
}

# The demlab executable, for tests that start a second process ("" when it is not known: the
# suite run from a plain tclsh outside ctest); constraint demlabExe.
set ::demlabExe ""
if {[info exists ::env(DEMLAB_EXE)]} {
    set ::demlabExe $::env(DEMLAB_EXE)
} elseif {[file tail [info nameofexecutable]] eq "demlab"} {
    set ::demlabExe [info nameofexecutable]
}
::tcltest::testConstraint demlabExe [expr {$::demlabExe ne ""}]

# How much slower than the Release build this build runs: 1, or what $DEMLAB_TIME_FACTOR says
# (the sanitizer build sets 5). Tests with a time limit scale it by this.
set ::timeFactor 1
if {[info exists ::env(DEMLAB_TIME_FACTOR)] && [string is double -strict $::env(DEMLAB_TIME_FACTOR)]} {
    set ::timeFactor $::env(DEMLAB_TIME_FACTOR)
}
