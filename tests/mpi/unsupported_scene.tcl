# A scene distributed runs do not support yet (2D): the first run raises MPI UNSUPPORTED on every
# rank, and the script, not catching it, ends with it (once, from rank 0).
sim new -dim 2
material add glass -density 2500 -young 1e7 -poisson 0.25 -restitution 0.5 -friction 0.4
element add -radius 0.001 -position {0 0}
element add -radius 0.001 -position {0.003 0}
sim run -steps 10 -quiet
