# One rank fails alone (as when it cannot write a file) while the others step the scene: the
# run must end with an error, not wait for ever (demlab aborts it).
sim new
material add glass -density 2500 -young 1e7 -poisson 0.25 -restitution 0.5 -friction 0.4
wall add plane -normal {0 0 1}
pack lattice -region {box {0 0 0} {0.02 0.02 0.02}} -radius 0.001
behavior add gravity
sim run -steps 10 -quiet
if {[dict get [sim ranks] rank] == [dict get [sim ranks] ranks] - 1} {
    error "the last rank fails alone" {} {TEST ALONE}
}
sim run -steps 100000000 -quiet
