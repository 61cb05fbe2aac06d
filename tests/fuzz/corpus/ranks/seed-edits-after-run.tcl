# A seed of tests/fuzz/ranks_fuzz.tcl: the fuzzer's scene spread over the ranks by a run, then
# edits each rank must take or refuse alike (tags, loads, a bond, a law, an element added and
# removed, a checkpoint), each followed by a run.
set steps {
    {sim new -dim 3}
    {material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5}
    {material add steel -density 7800 -young 2e8 -poisson 0.3 -restitution 0.5 -friction 0.3}
    {wall add plane -normal {0 0 1} -name floor}
    {wall add plane -normal {1 0 0} -point {-0.05 0 0}}
    {wall add plane -normal {-1 0 0} -point {0.05 0 0} -tags lids}
    {wall add plane -normal {0 1 0} -point {0 -0.05 0}}
    {wall add plane -normal {0 -1 0} -point {0 0.05 0}}
    {element add -radius 0.01 -position {0 0 0.0105} -name first -tags grains}
    {element add -radius 0.01 -position {0.02 0 0.0105} -tags grains}
    {pack random -region {box {-0.045 -0.045 0.025} {0.045 0.045 0.08}} -radius 0.004 -count 120 -seed 3}
    {behavior add gravity}
    {sim run -steps 20 -quiet}
    {element tag more first 1}
    {behavior add load -tag more -force {0 0 1e-4}}
    {sim run -steps 20 -quiet}
    {bond model pointspring glue -kn 1e5 -ks 1e5 -tensile 1 -shear 1}
    {bond add -model glue -gap 1e-3}
    {law pair glass steel linear}
    {element add -radius 0.004 -position {0 0 0.09} -name late}
    {sim run -steps 20 -quiet}
    {element remove late}
    {element untag more first}
    {sim save base.ckpt}
    {sim run -steps 20 -quiet}
    {sim load base.ckpt}
    {sim run -steps 20 -quiet}
    {query energy}
    {element count -tag grains}
}
