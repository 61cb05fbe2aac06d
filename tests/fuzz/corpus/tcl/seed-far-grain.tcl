# A seed of the command fuzzer's corpus: a grain far from the origin (a signed overflow in the
# snapshot renderer and non-finite masses before the validity policy), and a size distribution
# with an absurd exponent.
set steps {
    {sim new}
    {material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5}
    {element add -radius 0.01 -position {1e300 0 0}}
    {element add -radius 1e200}
    {element add -radius 0.01 -position {1e14 0 0}}
    {snapshot write far.png -size 32x24}
    {pack random -region {box {0 0 0} {0.1 0.1 0.1}} -radius {powerlaw 0.001 0.002 1e308} -count 1}
    {sim step}
}
