# A sequence found by tests/fuzz/command_fuzz.tcl (seed 11): violation
# the scene changed although the command failed: bad box 0: coordinate is infinite on axis 0
set steps {
    {sim new -dim 3}
    {material add steel -density 7800 -young 2e8 -poisson 0.3 -restitution 0.5 -friction 0.3}
    {element add -radius 0.005 -position {0.1 0.1 0.1} -material steel}
    {module detection -cellfactor 0.01 -skin 1e300}
    {sim step}
}
