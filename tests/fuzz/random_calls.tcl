# Random calls of demlab's commands built from their declarations, and the minimisation and
# saving of a failing sequence: shared by the command-sequence fuzzers (command_fuzz.tcl, one
# process; ranks_fuzz.tcl, under mpirun). Needs tests/tcl/declcalls.tcl.

# Returns a word for parameter p of decl: mostly a valid one, sometimes a bad or boundary one.
proc randomWord {decl p} {
    if {rand() < 0.75} {
        set w [validWord $decl $p]
        if {[dict get $p kind] eq "real" && rand() < 0.5} {
            set pick [lindex {0.005 0.01 0.02 0.1} [expr {int(rand() * 4)}]]
            if {![outsideRange $p $pick]} {set w $pick}
        }
        return $w
    }
    set words [badWords $p]
    if {$words eq {}} {return [validWord $decl $p]}
    lindex [lindex $words [expr {int(rand() * [llength $words])}]] 0
}

# Returns a random call of decl: its required parameters, some optional ones.
proc randomCall {decl} {
    set call [dict get $decl command]
    set options {}
    set chosen {}
    foreach g [dict get $decl exclusive] {
        set names [dict get $g names]
        if {[dict get $g requireone] || rand() < 0.3} {
            lappend chosen [lindex $names [expr {int(rand() * [llength $names])}]]
        }
        foreach n $names {if {$n ni $chosen} {lappend excluded $n}}
    }
    foreach p [dict get $decl params] {
        set n [dict get $p name]
        set role [dict get $p role]
        set wanted [expr {[dict get $p required] || $n in $chosen
            || (![info exists excluded] || $n ni $excluded) && rand() < 0.25}]
        if {!$wanted} continue
        switch -- $role {
            positional - variadic {lappend call [randomWord $decl $p]}
            flag {lappend options -$n}
            option {lappend options -$n [randomWord $decl $p]}
        }
    }
    concat $call $options
}

# Returns a call that sets up a callback into demlab from inside another command: puts
# redirected to a command, a load whose force expression runs one, a kept puts restored.
proc randomCallback {decls} {
    set inner [randomCall [lindex $decls [expr {int(rand() * [llength $decls])}]]]
    switch -- [expr {int(rand() * 4)}] {
        0 {return [list proc ::puts args $inner]}
        1 {return [list proc ::puts args "catch [list $inner]; ::fuzz_puts {*}\$args"]}
        2 {
            return [list behavior add load -element first \
                -force [list 0 0 "\[catch [list $inner]\] * 0.0"]]
        }
        3 {
            return [list study convergence -scene ::valid::tinyScene -steps 1 -quiet \
                -measure "[list catch $inner]; expr 1.0"]
        }
    }
}

# Returns 1 if result is a failure of the same kind as the one being minimised.
proc sameFailure {result target} {
    expr {[dict get $result status] eq [dict get $target status]
          && [lindex [dict get $result rule] 0] eq [lindex [dict get $target rule] 0]}
}

# Returns the smallest sublist of steps found (delta debugging: dropping chunks, then single
# steps) that still fails the way target does when run by the command prefix `run` (called
# with a list of steps, returning a result dict with status and rule).
proc minimise {steps target run} {
    set chunk [expr {max(1, [llength $steps] / 2)}]
    while {$chunk >= 1} {
        set progress 0
        for {set start 0} {$start < [llength $steps]} {incr start $chunk} {
            set trial [lreplace $steps $start [expr {$start + $chunk - 1}]]
            if {$trial eq {}} continue
            if {[sameFailure [{*}$run $trial] $target]} {
                set steps $trial
                set progress 1
                incr start -$chunk
            }
        }
        if {!$progress} {set chunk [expr {$chunk / 2}]}
    }
    return $steps
}


# Runs random command sequences for the given seconds from seed: each made by the command
# prefix `generate` (called with the declarations and a length) and run by `run` (called with
# the steps; returns a result dict: status ok, slow or a failure's, rule, message, the failing
# step, and the counts commands, errors and those named in `sums`). A failing sequence is cut
# after its failing step, minimised by `minimiser` (called with the steps and the result;
# returns the steps kept) and saved in corpus, `origin` naming what found it. Returns the
# counts summed over the sequences, with sequences, slow, findings, hangs and elapsed seconds.
proc fuzzLoop {seconds seed generate run minimiser corpus origin {sums {}}} {
    set decls [help -declarations]
    expr {srand($seed)}
    set started [clock milliseconds]
    set deadline [expr {$started + int($seconds * 1000)}]
    set counts [dict create sequences 0 commands 0 errors 0 slow 0 findings 0 hangs 0]
    foreach key $sums {dict set counts $key 0}
    while {[clock milliseconds] < $deadline} {
        set steps [{*}$generate $decls 20]
        set result [{*}$run $steps]
        dict incr counts sequences
        foreach key [list commands errors {*}$sums] {dict incr counts $key [dict get $result $key]}
        set status [dict get $result status]
        if {$status eq "slow"} {dict incr counts slow}
        if {$status in {ok slow}} continue
        dict incr counts findings
        if {$status eq "hang"} {dict incr counts hangs}
        puts "finding: $status [dict get $result rule]"
        # What follows the command that failed, crashed or hung does not matter.
        set steps [lrange $steps 0 [dict get $result step]]
        set small [{*}$minimiser $steps $result]
        set path [saveFinding $corpus $small $result $origin]
        puts "  minimised from [llength $steps] to [llength $small] commands: $path"
    }
    dict set counts elapsed [expr {([clock milliseconds] - $started) / 1000.0}]
    return $counts
}

# Saves a minimised failing sequence as a Tcl file in dir, its first line naming what found it
# (origin, e.g. "tests/fuzz/command_fuzz.tcl (seed 3)"). Returns the file's path.
proc saveFinding {dir steps result origin} {
    file mkdir $dir
    set body "# A sequence found by $origin: [dict get $result status]\n"
    foreach line [split "[dict get $result rule]: [dict get $result message]" \n] {
        append body "# $line\n"
    }
    append body "set steps {\n"
    foreach s $steps {append body "    [list $s]\n"}
    append body "}\n"
    set name [format "%s-%08x.tcl" [dict get $result status] [expr {[zlib crc32 $steps] & 0xffffffff}]]
    set path [file join $dir $name]
    set f [open $path w]
    puts -nonewline $f $body
    close $f
    return $path
}

# Returns the saved sequences that paths name: files, and the *.tcl files of folders, sorted.
proc sequenceFiles {paths} {
    set files {}
    foreach p $paths {
        if {[file isdirectory $p]} {
            lappend files {*}[lsort [glob -nocomplain -directory $p *.tcl]]
        } else {
            lappend files $p
        }
    }
    return $files
}
