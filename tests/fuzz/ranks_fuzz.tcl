# The distributed command-sequence fuzzer: random sequences of demlab commands (the same calls
# as command_fuzz.tcl's, from the declarations) run as one script by every rank of
# `mpirun -np N demlab`, in a 3D scene that distributes at its first run. Each rank records
# the outcome of every command (ok and a checksum of its result, or its -errorcode and a
# checksum of its message) in a file of its own; the driver checks:
#   - the run ends (a sequence still running after its timeout gets SIGINT, which a
#     distributed run obeys on every rank at the same step; one that does not end 15 s later
#     is killed) and no rank crashes (the script catches every error, so it exits 0);
#   - every rank saw the same outcome of every command: the same result (a query answers for
#     the whole scene on every rank), or the same error; an error raised on some ranks only
#     would leave the others waiting in the next collective (a hang, when the ranks' records
#     differ in length at the timeout);
#   - an error has an -errorcode starting DEMLAB, and not DEMLAB INTERNAL.
# A failing sequence is minimised (delta debugging, each trial a new mpirun) and saved as a Tcl
# file in the corpus; `replay` runs saved ones again.
#
# Usage (through a demlab executable, which runs the driver alone):
#   demlab ranks_fuzz.tcl fuzz -mpiexec PATH -demlab PATH ?-np N? ?-seconds N? ?-seed S?
#          ?-corpus DIR? ?-timeout SECONDS?
#   demlab ranks_fuzz.tcl replay -mpiexec PATH -demlab PATH ?-np N? PATH ...
# fuzz prints one line of figures at the end and exits 1 when it found a failing sequence;
# replay exits 1 when a saved sequence still fails.

set here [file dirname [file normalize [info script]]]
source [file join $here .. tcl declcalls.tcl]
source [file join $here random_calls.tcl]

namespace eval ranks {
    variable mpiexec ""
    variable demlab ""
    variable np 2
    variable timeout 60
    variable work ""        ;# the folder the sequences run in, made anew for each
}

# Returns the calls that build the scene a sequence starts from: the names and files the valid
# words refer to (tests/tcl/declcalls.tcl: materials glass and steel, a grain named first in
# tag grains, a wall named floor, a kept scene base, base.ckpt, base.data, base.png, pairs.txt),
# in a box of plane walls with a bed of grains spread over the ranks by a first run. Only what
# distributed runs support: the fuzzed calls add the rest (bonds, inlets, shapes), which must
# be refused alike on every rank.
proc ranksSceneSteps {} {
    list {sim new -dim 3} \
        {material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5} \
        {material add steel -density 7800 -young 2e8 -poisson 0.3 -restitution 0.5 -friction 0.3} \
        {wall add plane -normal {0 0 1} -name floor} \
        {wall add plane -normal {1 0 0} -point {-0.05 0 0}} \
        {wall add plane -normal {-1 0 0} -point {0.05 0 0} -tags lids} \
        {wall add plane -normal {0 1 0} -point {0 -0.05 0}} \
        {wall add plane -normal {0 -1 0} -point {0 0.05 0}} \
        {element add -radius 0.01 -position {0 0 0.0105} -name first -tags grains} \
        {element add -radius 0.01 -position {0.02 0 0.0105} -tags grains} \
        {element add -radius 0.005 -position {0.03 0.03 0.04} -material steel} \
        {pack random -region {box {-0.045 -0.045 0.025} {0.045 0.045 0.08}} -radius 0.004 \
             -count 120 -seed 3} \
        {behavior add gravity} \
        {behavior add load -element 0 -force {0 0 1e-4}} \
        {series every -steps 1000 -quantities {time kinetic}} \
        {dump every -steps 1000 -dir dumps} \
        {sim save base.ckpt} {dump lammps base.data} {snapshot write base.png -size 16x12} \
        {sim keep base} \
        {sim run -steps 20 -quiet}
}

# Returns a random sequence: the scene above (or, one time in ten, a bare 2D one, which
# distributed runs refuse), then up to `length` random calls and callbacks, one in five
# followed by a short run (the collective step: migration, ghosts and outputs after the edit).
proc randomRanksSequence {decls length} {
    set steps [expr {rand() < 0.9 ? [ranksSceneSteps] : [list {sim new -dim 2}]}]
    set n [expr {1 + int(rand() * $length)}]
    for {set k 0} {$k < $n} {incr k} {
        if {rand() < 0.1} {
            lappend steps [randomCallback $decls]
        } else {
            lappend steps [randomCall [lindex $decls [expr {int(rand() * [llength $decls])}]]]
        }
        if {rand() < 0.2} {lappend steps {sim run -steps 20 -quiet}}
    }
    return $steps
}

# Returns the script every rank runs for steps: it records each command's outcome in
# rank<R>.txt in the folder given as its argument, which it works in (and where the driver
# wrote pairs.txt).
proc ranksScript {steps} {
    set declcalls [file join $::here .. tcl declcalls.tcl]
    set body [string map [list @DECLCALLS@ [list $declcalls]] {
        source @DECLCALLS@
        cd [lindex $argv 0]
        set fuzzOut [open rank[dict get [sim ranks] rank].txt w]
        # One line a command: its index, 1 if it failed, its -errorcode, its first two words
        # and a checksum of its result or message.
        proc fuzzStep {k call} {
            set failed [catch {uplevel #0 $call} msg opts]
            set code [expr {$failed ? [dict get $opts -errorcode] : ""}]
            chan puts $::fuzzOut [list $k $failed $code [lrange $call 0 1] [zlib crc32 $msg]]
            chan flush $::fuzzOut
            # Only the driver interrupts (a sequence past its timeout): the rest is not wanted.
            if {$failed && [lindex $code 1] eq "INTERRUPTED"} {exit 0}
        }
    }]
    set k 0
    foreach s $steps {
        append body "fuzzStep $k [list $s]\n"
        incr k
    }
    return $body
}

# Returns what every rank must agree on in a record line: the command's index, whether it
# failed, its -errorcode, and its result or message, except where that holds the rank's own
# figures (`sim ranks`: its part; the reports of runs and studies: their wall-clock times).
proc outcomeOf {line} {
    lassign $line index failed code words sum
    if {!$failed && ($words in {{sim ranks} {sim run} {sim step}} || [lindex $words 0] eq "study")} {
        set sum ""
    }
    list $index $failed $code $sum
}

# Reads the records of a run's ranks. Returns a list with one list of lines a rank.
proc ranksRecords {dir} {
    set all {}
    for {set r 0} {$r < $ranks::np} {incr r} {
        set lines {}
        set path [file join $dir rank$r.txt]
        if {[file exists $path]} {
            set f [open $path]
            foreach line [split [string trimright [read $f] \n] \n] {
                if {$line ne ""} {lappend lines $line}
            }
            close $f
        }
        lappend all $lines
    }
    return $all
}

# Runs steps under mpirun. Returns a dict: status (ok, slow: ended by its SIGINT, crash, hang
# or violation), commands (how many every rank finished), errors (how many of those failed)
# and unsupported (failed as what distributed runs do not support: DEMLAB MPI UNSUPPORTED), and
# for a failure step, rule and message.
proc runRanks {steps} {
    set dir [file join $ranks::work seq]
    file delete -force $dir
    file mkdir $dir
    # Written here, once: ranks writing it each would truncate it under another's reading.
    writePairsFile [file join $dir pairs.txt]
    set script [file join $ranks::work seq.tcl]
    set f [open $script w]
    puts $f [ranksScript $steps]
    close $f
    set log [file join $ranks::work log.txt]
    set exit 0
    if {[catch {exec timeout -s INT -k 15 $ranks::timeout $ranks::mpiexec -np $ranks::np \
                    $ranks::demlab $script $dir >& $log} msg opts]} {
        set code [dict get $opts -errorcode]
        set exit [expr {[lindex $code 0] eq "CHILDSTATUS" ? [lindex $code 2] : -1}]
    }
    set records [ranksRecords $dir]
    set lengths [lmap r $records {llength $r}]
    set done [tcl::mathfunc::min {*}$lengths]
    set result [dict create status ok commands $done errors 0 unsupported 0]
    foreach line [lrange [lindex $records 0] 0 [expr {$done - 1}]] {
        lassign $line index failed code
        if {$failed} {dict incr result errors}
        if {[lrange $code 0 2] eq {DEMLAB MPI UNSUPPORTED}} {dict incr result unsupported}
    }
    set f [open $log]
    set output [string range [read $f] 0 3000]
    close $f
    # The first command whose outcome differs between ranks, or that failed with a bad code.
    for {set k 0} {$k < $done} {incr k} {
        set outcomes [lsort -unique [lmap r $records {outcomeOf [lindex $r $k]}]]
        if {[llength $outcomes] > 1} {
            return [dict merge $result [dict create status violation step $k \
                rule "ranks disagree" message [join $outcomes " | "]]]
        }
        lassign [lindex $outcomes 0] index failed code
        set command [lindex [lindex $records 0 $k] 3 0]
        if {$failed && $command ni {proc rename}
                && ([lindex $code 0] ne "DEMLAB" || [lindex $code 1] eq "INTERNAL")} {
            return [dict merge $result [dict create status violation step $k \
                rule "errorcode {$code}" message [lindex $steps $k]]]
        }
    }
    switch -- $exit {
        0 {}
        124 {
            # Timed out, then ended by its SIGINT: a hang only if the ranks stopped at
            # different commands (some wait in a collective the others left).
            dict set result status [expr {[llength [lsort -unique $lengths]] > 1 ? "hang" : "slow"}]
            if {[dict get $result status] eq "hang"} {
                dict set result step $done
                dict set result rule hang
                dict set result message "ranks stopped after $lengths commands: $output"
            }
        }
        137 {
            return [dict merge $result [dict create status hang step $done rule hang \
                message "killed 15 s after SIGINT at $lengths commands: $output"]]
        }
        default {
            return [dict merge $result [dict create status crash step $done \
                rule "exit status $exit" message $output]]
        }
    }
    if {[dict get $result status] eq "ok" && $done < [llength $steps]} {
        return [dict merge $result [dict create status crash step $done \
            rule "a rank stopped early" message "records $lengths of [llength $steps]: $output"]]
    }
    return $result
}

# Fuzzes for the given seconds from seed. Returns the number of findings; prints the figures.
proc ranksFuzz {seconds seed corpus} {
    set c [fuzzLoop $seconds $seed randomRanksSequence runRanks \
        {apply {{steps result} {minimise $steps $result runRanks}}} $corpus \
        "tests/fuzz/ranks_fuzz.tcl (seed $seed, $ranks::np ranks)" unsupported]
    puts "ranks_fuzz: seed $seed, $ranks::np ranks, [dict get $c sequences] sequences,\
        [dict get $c commands] commands ([dict get $c errors] failed, as they may;\
        [dict get $c unsupported] of them refused as unsupported on ranks) in [dict get $c elapsed]\
        s, [dict get $c findings] findings, [dict get $c slow] interrupted after $ranks::timeout s"
    return [dict get $c findings]
}

# Replays saved sequences; returns the number that still fail.
proc ranksReplay {paths} {
    set failures 0
    set files [sequenceFiles $paths]
    foreach f $files {
        unset -nocomplain steps
        source $f
        set result [runRanks $steps]
        if {[dict get $result status] ni {ok slow}} {
            incr failures
            puts "FAILED $f: [dict get $result status] [dict get $result rule]\
                [dict get $result message]"
        }
    }
    puts "ranks_fuzz replay: [llength $files] sequences, $failures failing"
    return $failures
}

# Sets the driver's options from a dict of -name value. Returns nothing.
proc ranksOptions {opts} {
    foreach {name var} {-mpiexec mpiexec -demlab demlab -np np -timeout timeout} {
        if {[dict exists $opts $name]} {set ranks::$var [dict get $opts $name]}
    }
    if {$ranks::mpiexec eq "" || $ranks::demlab eq ""} {
        puts stderr "ranks_fuzz: -mpiexec and -demlab are needed"
        exit 2
    }
    set ranks::work [file join [expr {[info exists ::env(TMPDIR)] ? $::env(TMPDIR) : "/tmp"}] \
        demlab-ranks-fuzz-[pid]]
    file mkdir $ranks::work
}

set mode [lindex $argv 0]
switch -- $mode {
    fuzz {
        set opts [dict merge {-seconds 60 -seed 1 -corpus ""} [lrange $argv 1 end]]
        ranksOptions $opts
        set corpus [dict get $opts -corpus]
        if {$corpus eq ""} {set corpus [file join $here corpus ranks]}
        set n [ranksFuzz [dict get $opts -seconds] [dict get $opts -seed] $corpus]
        file delete -force $ranks::work
        exit [expr {$n > 0}]
    }
    replay {
        set args [lrange $argv 1 end]
        set opts {}
        while {[string match -* [lindex $args 0]]} {
            dict set opts [lindex $args 0] [lindex $args 1]
            set args [lrange $args 2 end]
        }
        ranksOptions $opts
        set n [ranksReplay $args]
        file delete -force $ranks::work
        exit [expr {$n > 0}]
    }
    default {
        puts stderr "usage: demlab ranks_fuzz.tcl fuzz -mpiexec PATH -demlab PATH ?-np N?\
            ?-seconds N? ?-seed S? ?-corpus DIR? ?-timeout SECONDS? | replay -mpiexec PATH\
            -demlab PATH ?-np N? PATH ..."
        exit 2
    }
}
