# Measures how long each long-running command takes to answer Ctrl-C on a large scene: for each
# command, a child demlab loads the scene, starts the command, and gets SIGINT after each of a
# range of delays; the child notes when the command returned. Prints CSV:
#   command,delay_ms,latency_ms,outcome
# (outcome: the error code, or "finished" when the command ended before the signal).
# Run by scripts/interrupt-latency, which builds demlab first:
#   demlab scripts/interrupt-latency.tcl ?-side METRES? ?-delays {ms ...}? ?-out DIR? ?-only GLOB?
# -side sets the lattice block (radius 1 mm): 0.16 gives 512 000 grains. -only runs the commands
# matching a glob pattern (string match), e.g. "sim *".

set opts [dict merge {-side 0.16 -delays {10 50 100 200 300 400 600 800 1000 1500 2000} -out "" -only *} $argv]
set exe [info nameofexecutable]
set dir [dict get $opts -out]
if {$dir eq ""} {set dir [file join /tmp demlab-latency-[pid]]}
file mkdir $dir
set side [dict get $opts -side]

# The scenes: a bed in a lattice (bonds to make), the same bonded and stepped once (contacts,
# bonds, large results), and its LAMMPS data file.
set plain [file join $dir plain.ck]
set bonded [file join $dir bonded.ck]
set data [file join $dir bed.data]
set make [file join $dir make.tcl]
set f [open $make w]
puts $f [string map [list @SIDE@ $side @PLAIN@ $plain @BONDED@ $bonded @DATA@ $data] {
    sim new
    material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5
    pack lattice -region {box {0 0 0} {@SIDE@ @SIDE@ @SIDE@}} -radius 0.001
    behavior add gravity
    wall add plane -point {0 0 0} -normal {0 0 1}
    sim timestep auto
    bond model pointspring ps -kn 1e6 -ks 1e6 -tensile 1e3 -shear 1e3
    sim save @PLAIN@
    dump lammps @DATA@
    bond add -model ps -gap 1e-5
    sim step 1
    sim save @BONDED@
    puts stderr "scene: [dict get [sim info] elements] grains, [dict get [bond count] bonds] bonds"
}]
close $f
exec $exe $make 2>@stderr

# Returns {latency outcome} of `command` run after `setup` with SIGINT after delay ms.
proc interrupted {setup command delay} {
    global exe dir
    set child [file join $dir child.tcl]
    set f [open $child w]
    puts $f "$setup
puts ready; flush stdout
set code \[catch {$command} msg opts\]
puts \[list \[clock milliseconds\] \$code \[expr {\$code ? \[dict get \$opts -errorcode\] : {}}\]\]
flush stdout"
    close $f
    set chan [open |[list $exe $child 2>@1] r]
    gets $chan line
    if {$line ne "ready"} {catch {close $chan}; return [list "" "child: $line"]}
    after $delay
    set sent [clock milliseconds]
    catch {exec kill -INT [pid $chan]}
    set line [gets $chan]
    catch {close $chan}
    lassign $line done code errorcode
    if {![string is wide -strict $done]} {return [list "" "child: $line"]}
    if {!$code} {return [list "" finished]}
    list [expr {$done - $sent}] [join $errorcode " "]
}

set load "sim load [list $plain]"
set loadBonded "sim load [list $bonded]"
# Each case: its label in the CSV, the command, and the setup before it.
set cases [list \
    "sim step" "sim step 1000000" $loadBonded \
    "sim step (5 mm skin)" "sim step 1" "$load; module detection -skin 0.005" \
    "sim run" "sim run -steps 1000000 -quiet" "$loadBonded; sim step 2" \
    "sim relax" "sim relax -overlap 1e-12 -iterations 1000000" "$loadBonded; element resize -factor 1.01" \
    "pack file" "pack file [list $data]" "sim new; material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5" \
    "bond add" "bond add -model ps -gap 1e-5" $load \
    "sim save" "sim save [list [file join $dir out.ck]]" $loadBonded \
    "sim digest" "sim digest" $loadBonded \
    "sim keep" "sim keep copy" $loadBonded \
    "query contacts" "query contacts" $loadBonded \
    "bond list" "bond list" $loadBonded \
    "dump vtk" "dump vtk [list [file join $dir out]]" $loadBonded \
    "snapshot write" "snapshot write [list [file join $dir out.png]] -size 4000x4000" "$loadBonded; snapshot write [list [file join $dir warm.png]] -size 16x16" \
]
puts "command,delay_ms,latency_ms,outcome"
foreach {label command setup} $cases {
    if {![string match [dict get $opts -only] $label]} continue
    foreach delay [dict get $opts -delays] {
        lassign [interrupted $setup $command $delay] latency outcome
        puts "$label,$delay,$latency,$outcome"
        flush stdout
        if {$outcome eq "finished"} break
    }
}
file delete -force $dir
