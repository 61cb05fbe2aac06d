# A sequence found by tests/fuzz/command_fuzz.tcl (seed 5): violation
# the scene changed although the command failed: bad velocity "1e+300 1e+300 1e+300": must be at most 1000000 m/s in magnitude
set steps {
    {sim new -dim 3}
    {material add steel -density 7800 -young 2e8 -poisson 0.3 -restitution 0.5 -friction 0.3}
    {element add -radius 0.01 -position {0 0 0.0105} -name first -tags grains}
    {element set first -position {0 0 1} -velocity {1e300 1e300 1e300} -angularvelocity {0 0 1}}
}
