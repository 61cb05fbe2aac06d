# A seed of the command fuzzer's corpus: a redirected puts that replaces the scene a running
# command holds (a use-after-free before commands that change the scene were refused while
# another runs).
set steps {
    {sim new}
    {material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5}
    {element add -radius 0.01}
    {sim timestep 1}
    {proc ::puts args {sim new}}
    {sim run -steps 3}
    {proc ::puts args {catch {sim new}; catch {element add -radius 0.01}}}
    {sim run -steps 3}
    {behavior add load -element 0 -force {0 0 {[catch {sim new}] * 0.0}}}
    {sim run -steps 3 -quiet}
}
