# A sequence found by tests/fuzz/ranks_fuzz.tcl (seed 61, 2 ranks): violation
# ranks disagree: 27 1 {DEMLAB WATCHDOG OVERLAP} 1407283062 | 27 1 {DEMLAB WATCHDOG OVERLAP} 3455498555
set steps {
    {sim new -dim 3}
    {material add steel -density 7800 -young 2e8 -poisson 0.3 -restitution 0.5 -friction 0.3}
    {pack random -region {box {-0.045 -0.045 0.025} {0.045 0.045 0.08}} -radius 0.004  -count 120 -seed 3}
    {wall add plane -normal {-1e308 -1e308 -1e308} -frequency 1.0}
    {sim run -steps 20 -quiet}
}
