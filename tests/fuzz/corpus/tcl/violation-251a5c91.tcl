# A sequence found by tests/fuzz/command_fuzz.tcl (seed 11): violation
# the scene changed although the command failed: bad velocity "-1.1128156588845584e+299 -1.114705983472839e+299 5.2578878382352205e+299": must be at most 1000000 m/s in magnitude
set steps {
    {sim new -dim 3}
    {material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5}
    {inlet add fresh -region {box {-0.05 -0.05 0.4} {0.05 0.05 0.5}} -radius 0.002 -massrate 1.0 -jitter 1e300 -tolerance 1e-300}
    {sim step}
}
