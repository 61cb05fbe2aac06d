# The command-sequence fuzzer: random sequences of demlab commands built from the declarations
# (help -declarations, through tests/tcl/declcalls.tcl), with valid words, bad and boundary
# words, and re-entrant callbacks (a redirected puts, a load expression, a study's scripts that
# call other commands). Each sequence runs in a fresh interpreter of a runner process; after
# every command the runner checks the invariants:
#   - an error has an -errorcode starting DEMLAB, and not DEMLAB INTERNAL;
#   - a command that fails leaves `sim digest` unchanged (except the outcomes documented as
#     partial: the watchdog's stop, an interrupt, a failing load expression);
#   - the scene's energies, bounds and element positions are finite.
# The driver runs the runner as a child process, so a crash (the runner dies) or a hang (no
# answer, even to SIGINT) is seen too. A failing sequence is minimised (delta debugging on its
# list of commands) and saved as a Tcl file in the corpus, which `replay` runs again.
#
# Usage (through the demlab executable):
#   demlab command_fuzz.tcl fuzz ?-seconds N? ?-seed S? ?-corpus DIR? ?-timeout SECONDS?
#   demlab command_fuzz.tcl replay PATH ...     (saved sequences: files, or folders of *.tcl)
#   demlab command_fuzz.tcl runner              (internal: the child the driver talks to)
# fuzz prints one line of figures at the end: sequences, commands, seconds, findings; it exits 1
# when it found a crash or a broken invariant (a hang, work inside one command that Ctrl-C
# cannot stop, is saved and counted but is a known open problem: doc/reliability.md). replay
# exits 1 when a saved sequence still fails.

set here [file dirname [file normalize [info script]]]
source [file join $here .. tcl declcalls.tcl]
source [file join $here random_calls.tcl]

# ---------------------------------------------------------------------------------------------
# The runner: runs sequences, checking the invariants after each command.

# Returns the scene's digest in interpreter fz, or "" when it has no scene.
proc digestOf {fz} {
    if {[catch {$fz eval {sim digest}} d]} {return ""}
    return $d
}

# Returns "" if what the scene in fz reports is finite, else the first non-finite report.
proc nonFinite {fz} {
    foreach q {{query energy} {query bounds} {element array position -flat}
               {element array velocity -flat}} {
        if {[catch {$fz eval $q} value]} continue
        if {[regexp -nocase {nan|inf} $value]} {return "$q gave [string range $value 0 200]"}
    }
    return ""
}

# Whether a failure is one documented as leaving the steps done (doc/reliability.md), so the
# digest may change: a run the watchdog stopped after some steps, or an interrupted one. A
# watchdog stop before the run's first step and a failing script callback change nothing.
proc partialOutcome {code message} {
    switch -- [lindex $code 1] {
        INTERRUPTED {return 1}
        WATCHDOG {return [expr {![string match {*before the first step*} $message]}]}
        default {return 0}
    }
}

# Runs one sequence (a list of calls, each a list of words) in a fresh interpreter. Returns a
# dict: commands (how many ran), status (ok or violation), and for a violation, step (its
# index), rule, and message.
proc runSequence {steps} {
    set fz [interp create]
    load {} Demlab $fz
    $fz eval {namespace import ::demlab::*}
    # The reports of runs go nowhere, unless a sequence redirects puts itself.
    $fz eval {rename ::puts ::fuzz_puts; proc ::puts args {}}
    cd $::runnerDir
    set result [dict create commands 0 errors 0 status ok]
    set i 0
    foreach call $steps {
        # Which command runs, for the driver to name if this one crashes or hangs.
        puts "FUZZSTEP $i"
        set before [digestOf $fz]
        set failed [catch {$fz eval $call} msg opts]
        dict incr result commands
        if {$failed} {dict incr result errors}
        set rule ""
        if {$failed && [lindex $call 0] ni {proc rename}} {
            set code [dict get $opts -errorcode]
            if {[lindex $code 0] ne "DEMLAB" || [lindex $code 1] eq "INTERNAL"} {
                set rule "errorcode {$code}"
            } elseif {![partialOutcome $code $msg] && [digestOf $fz] ne $before} {
                set rule "the scene changed although the command failed"
            }
        }
        if {$rule eq ""} {
            set bad [nonFinite $fz]
            if {$bad ne ""} {set rule "non-finite: $bad"}
        }
        if {$rule ne ""} {
            dict set result status violation
            dict set result step $i
            dict set result rule $rule
            dict set result message [string range $msg 0 300]
            break
        }
        # Only the driver interrupts (a sequence past its timeout): the rest of the sequence
        # is not wanted, and its next long command would look like a hang.
        if {$failed && [lindex [dict get $opts -errorcode] 1] eq "INTERRUPTED"} break
        incr i
    }
    interp delete $fz
    return $result
}

# Returns the folder where the runner with process id pid works.
proc runnerFolder {pid} {
    file join [expr {[info exists ::env(TMPDIR)] ? $::env(TMPDIR) : "/tmp"}] \
        demlab-command-fuzz-$pid
}

# Reads sequences from stdin, one per line (newlines and backslashes escaped), and answers
# each with a line "FUZZRESULT <dict>". Returns at end of input.
proc runnerLoop {} {
    # What the sequences write (dumps, checkpoints, images) goes to a folder of this process.
    set ::runnerDir [runnerFolder [pid]]
    file mkdir $::runnerDir
    fconfigure stdout -buffering line
    while {[gets stdin line] >= 0} {
        set steps [string map {\\n \n \\\\ \\} $line]
        puts "FUZZRESULT [list [runSequence $steps]]"
        file delete -force $::runnerDir
        file mkdir $::runnerDir
    }
    file delete -force $::runnerDir
}

# ---------------------------------------------------------------------------------------------
# The driver: generates sequences and talks to a runner child.

namespace eval driver {
    variable ch ""          ;# the runner's pipe
    variable output ""      ;# what the runner wrote besides its answers (sanitizer reports)
    variable answer ""
    variable step 0         ;# the index of the command the runner last started
    variable timeout 20     ;# seconds a sequence may take before the runner is sent SIGINT
}

# Starts a runner child if none is running. Changes driver::ch.
proc driver::start {} {
    variable ch
    if {$ch ne ""} return
    set ch [open |[list [info nameofexecutable] [file normalize $::argv0] runner 2>@1] r+]
    fconfigure $ch -buffering line -blocking 0
    fileevent $ch readable driver::read
}

# Stops the runner child (closing its input; killed when it does not go). Changes driver::ch.
proc driver::stop {{signal ""}} {
    variable ch
    if {$ch eq ""} return
    set pids [pid $ch]
    if {$signal ne ""} {catch {exec kill -$signal {*}$pids}}
    fileevent $ch readable {}
    catch {fconfigure $ch -blocking 1}
    catch {close $ch}
    set ch ""
    # A runner that was killed leaves its folder (runnerLoop).
    foreach p $pids {file delete -force [runnerFolder $p]}
}

proc driver::read {} {
    variable ch
    variable output
    variable answer
    variable step
    if {[gets $ch line] >= 0} {
        if {[string match "FUZZRESULT *" $line]} {
            set answer [lindex [string range $line 11 end] 0]
        } elseif {[regexp {^FUZZSTEP (\d+)$} $line -> step]} {
        } else {
            append output $line \n
        }
    } elseif {[eof $ch]} {
        set answer eof
    }
}

# Runs a sequence on the runner. Returns the runner's result dict, or a dict with status
# crash (the runner died; output: what it printed), slow (no answer within the timeout, but
# the runner answered or ended within 5 s of a SIGINT: not a finding, long work is allowed) or
# hang (no answer even then). Restarts the runner after a crash, a slow sequence or a hang.
proc driver::run {steps} {
    variable ch
    variable output ""
    variable answer ""
    variable step 0
    variable timeout
    start
    puts $ch [string map {\\ \\\\ \n \\n} $steps]
    set timer [after [expr {int($timeout * 1000)}] {set driver::answer timeout}]
    vwait driver::answer
    after cancel $timer
    if {$answer eq "timeout"} {
        catch {exec kill -INT {*}[pid $ch]}
        set timer [after 5000 {set driver::answer hang}]
        vwait driver::answer
        after cancel $timer
        if {$answer ne "hang"} {
            stop KILL
            return [dict create status slow commands 0 errors 0 rule slow message ""]
        }
    }
    switch -- $answer {
        eof {
            stop KILL
            return [dict create status crash commands [expr {$step + 1}] errors 0 step $step \
                rule crash message [string range $output 0 2000]]
        }
        hang {
            stop KILL
            return [dict create status hang commands [expr {$step + 1}] errors 0 step $step rule hang \
                message "no answer in $timeout s, nor 5 s after SIGINT"]
        }
    }
    return $answer
}

# Returns a random sequence: the scene with one of everything (or a bare one), then up to
# `length` random calls and callbacks.
proc randomSequence {decls length} {
    set steps [expr {rand() < 0.8 ? [sceneSteps dumps] : [list {sim new -dim 2}]}]
    set n [expr {1 + int(rand() * $length)}]
    for {set k 0} {$k < $n} {incr k} {
        if {rand() < 0.1} {
            lappend steps [randomCallback $decls]
        } else {
            lappend steps [randomCall [lindex $decls [expr {int(rand() * [llength $decls])}]]]
        }
    }
    return $steps
}

# Fuzzes for the given seconds from seed. Returns the number of findings other than hangs;
# prints the figures.
proc fuzz {seconds seed corpus} {
    set c [fuzzLoop $seconds $seed randomSequence driver::run minimiseRun $corpus \
        "tests/fuzz/command_fuzz.tcl (seed $seed)"]
    driver::stop
    puts "command_fuzz: seed $seed, [dict get $c sequences] sequences, [dict get $c commands]\
        commands ([dict get $c errors] failed, as they may) in [dict get $c elapsed] s,\
        [dict get $c findings] findings ([dict get $c hangs] hangs), [dict get $c slow]\
        interrupted after [set driver::timeout] s"
    return [expr {[dict get $c findings] - [dict get $c hangs]}]
}

# Returns the steps of a failing sequence minimised (minimise); a hang is tried again with a
# shorter timeout.
proc minimiseRun {steps result} {
    set timeout $driver::timeout
    if {[dict get $result status] eq "hang"} {set driver::timeout [expr {min($timeout, 5)}]}
    set small [minimise $steps $result driver::run]
    set driver::timeout $timeout
    return $small
}

# Replays saved sequences; returns the number that still fail.
proc replay {paths} {
    set failures 0
    set files [sequenceFiles $paths]
    foreach f $files {
        unset -nocomplain steps
        source $f
        set result [driver::run $steps]
        if {[dict get $result status] ne "ok"} {
            incr failures
            puts "FAILED $f: [dict get $result status] [dict get $result rule]\
                [dict get $result message]"
        }
    }
    driver::stop
    puts "command_fuzz replay: [llength $files] sequences, $failures failing"
    return $failures
}

set mode [lindex $argv 0]
switch -- $mode {
    runner {
        runnerLoop
    }
    fuzz {
        set opts [dict merge {-seconds 60 -seed 1 -corpus "" -timeout 20} [lrange $argv 1 end]]
        set corpus [dict get $opts -corpus]
        if {$corpus eq ""} {set corpus [file join $here corpus tcl]}
        set driver::timeout [dict get $opts -timeout]
        exit [expr {[fuzz [dict get $opts -seconds] [dict get $opts -seed] $corpus] > 0}]
    }
    replay {
        exit [expr {[replay [lrange $argv 1 end]] > 0}]
    }
    default {
        puts stderr "usage: demlab command_fuzz.tcl fuzz ?-seconds N? ?-seed S? ?-corpus DIR?\
            ?-timeout SECONDS? | replay PATH ..."
        exit 2
    }
}
