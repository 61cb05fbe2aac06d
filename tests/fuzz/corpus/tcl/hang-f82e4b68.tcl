# A sequence found by tests/fuzz/command_fuzz.tcl (seed 11): hang
# hang: no answer in 20 s, nor 5 s after SIGINT
set steps {
    {sim new -dim 3}
    {material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5}
    {material add steel -density 7800 -young 2e8 -poisson 0.3 -restitution 0.5 -friction 0.3}
    {wall add plane -normal {0 0 1} -name floor}
    {wall add drum -point {0 0 0} -radius 0.5 -axis {0 1 0} -halflength 0.2}
    {element add -radius 0.01 -position {0 0 0.0105} -name first -tags grains}
    {element add -radius 0.01 -position {0.02 0 0.0105} -tags grains}
    {element add -radius 0.005 -position {0.1 0.1 0.1} -material steel}
    {bond model pointspring glue -kn 1e5 -ks 1e5 -tensile 1 -shear 1}
    {bond add -model glue -gap 1e-3}
    {behavior add gravity}
    {behavior add load -element 0 -force {0 0 1e-4}}
    {inlet add feed -region {box {-0.1 -0.1 0.2} {0.1 0.1 0.3}} -radius 0.002 -rate 10}
    {sink add drain -region {box {-1 -1 -1} {1 1 -0.5}}}
    {dump every -steps 1000 -dir dumps/dumps}
    {series every -steps 1000 -quantities {time kinetic}}
    {dump lammps base.data}
    {snapshot write base.png -size 16x12}
    {sim keep base}
    {element array id -tag grains}
    {module list}
    {sink list}
    {help sim}
    {pack random -region {box {-0.05 -0.05 0.4} {0.05 0.05 0.5}} -radius 0.002 -count 1}
    {pack random -region {box {-0.05 -0.05 0.4} {0.05 0.05 0.5}} -radius 0.002 -fraction 0.1 -velocity {0 0 1}}
    {pack lattice -region {box {-0.05 -0.05 0.4} {0.05 0.05 0.5}} -radius 1e308 -spacing 0.005 -material glass}
    {sim info}
    {wall add finite -normal {0 0 1} -halfextents {} -name a\{b -frequency 0.005}
    {query contacts -count}
    {bond add -model glue -gap 1e308}
    {proc ::puts args {catch {material list}; ::fuzz_puts {*}$args}}
    {element count}
}
