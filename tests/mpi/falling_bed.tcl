# A bed of balls falling into a box, the script a user runs alone or as `mpirun -np N demlab
# falling_bed.tcl`: every rank runs it, the first run spreads the scene over the ranks. It
# prints (rank 0 alone under mpirun) what script_ranks.sh compares between the two runs, and
# checks on its own what only a distributed run does: which commands are refused, and that an
# error raised on every rank is caught alike on every rank.
proc check {what ok} {
    if {!$ok} { error "falling_bed.tcl: $what" {} {TEST FAILED} }
}
proc expectError {code script} {
    set failed [catch {uplevel 1 $script} msg opts]
    check "\"$script\" should fail with $code, gave: $msg" \
        [expr {$failed && [string match $code* [dict get $opts -errorcode]]}]
}

sim new
material add glass -density 2500 -young 1e7 -poisson 0.25 -restitution 0.5 -friction 0.4
wall add plane -normal {0 0 1}
wall add plane -normal {1 0 0}
wall add plane -normal {-1 0 0} -point {0.04 0 0}
wall add plane -normal {0 1 0}
wall add plane -normal {0 -1 0} -point {0 0.04 0}
pack random -region {box {0.001 0.001 0.001} {0.039 0.039 0.06}} -radius {uniform 0.0014 0.002} \
    -count 1200 -seed 7
behavior add gravity
sim timestep 2e-5
set ranks [sim ranks]
check "no rank before the run should be distributed" [expr {![dict get $ranks distributed]}]

set report [sim run -steps 4000 -quiet]
set ranks [sim ranks]
set n [dict get $ranks ranks]
check "the scene is distributed when mpirun started more than one rank" \
    [expr {[dict get $ranks distributed] == ($n > 1)}]

# What the comparison reads: one key and its value a line.
puts "steps [dict get $report steps]"
puts "time [sim time]"
puts "rebuilds [dict get $report rebuilds]"
set counts [query counts]
puts "elements [dict get $counts elements]"
puts "walls [dict get $counts walls]"
puts "contacts [dict get $counts contacts]"
puts "count [element count]"
puts "bounds [join [query bounds]]"
set e [query energy]
foreach k {kinetic gravitational elastic damping friction wallwork} { puts "$k [dict get $e $k]" }
foreach id {0 1 17 600 1199} {
    puts "position$id [element get $id -position]"
    puts "velocity$id [element get $id -velocity]"
}
check "element get returns the dict with the id the script knows" \
    [expr {[dict get [element get 17] id] == 17 && [dict get [element get 17] radius] > 0}]

# Errors raised on every rank alike, caught alike.
expectError {DEMLAB LOOKUP ELEMENT} {element get 5000}
if {$n > 1} {
    expectError {DEMLAB MPI UNSUPPORTED} {element set 0 -velocity {0 0 0}}
    expectError {DEMLAB MPI UNSUPPORTED} {element add -radius 0.001 -position {0.02 0.02 0.1}}
    expectError {DEMLAB MPI UNSUPPORTED} {query contacts}
    expectError {DEMLAB MPI UNSUPPORTED} {sim save /tmp/never.dcp}
}
# The run goes on after them, together.
set report [sim run -steps 500 -quiet]
puts "contacts2 [dict get [query counts] contacts]"
puts "position2 [element get 600 -position]"
