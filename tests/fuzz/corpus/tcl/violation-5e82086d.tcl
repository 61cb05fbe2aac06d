# A sequence found by tests/fuzz/command_fuzz.tcl (seed 11): violation
# non-finite: query energy gave kinetic -NaN rotational -NaN gravitational 0.006163803379925494 elastic -NaN damping 0.0 friction 0.0 wallwork 0.0 behaviorwork -NaN balance -NaN scale 0.006163804786343174 residual NaN: run stopped at step 1 (t = 3.418049514612619e-05 s) by the watchdog: element 0 has a non-finite position or velocity; likely cause: the integration blew up (dt = 3.42e-05 s, critical estimate 0.000171 s), or a load or a wall motion gave a non-finite value; fix: use sim timestep auto (0.2 of the criti
set steps {
    {sim new -dim 3}
    {material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5}
    {element add -radius 0.01 -position {0 0 0.0105} -name first -tags grains}
    {behavior add torque-ramp -element first -rate {0 0 1} -start -1e308}
    {sim step 1}
}
