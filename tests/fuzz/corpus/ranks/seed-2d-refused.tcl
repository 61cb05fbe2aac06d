# A seed of tests/fuzz/ranks_fuzz.tcl: a 2D scene, which distributed runs refuse (DEMLAB MPI
# UNSUPPORTED on every rank), edited and run on after the refusal.
set steps {
    {sim new -dim 2}
    {material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5}
    {element add -radius 0.01 -position {0 0.0105}}
    {wall add plane -normal {0 1}}
    {behavior add gravity}
    {sim run -steps 10 -quiet}
    {element add -radius 0.01 -position {0.03 0.0105}}
    {sim run -steps 10 -quiet}
    {query counts}
}
