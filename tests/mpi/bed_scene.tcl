# The scene falling_bed.tcl and checkpoint_bed.tcl run: 1200 balls packed at random in a box of
# five plane walls, under gravity, at a fixed step. An element is made and removed first, so the
# bed's elements have ids other than their creation order (the first reuses its slot, id
# 2^32): distributed runs and their checkpoints must keep them. Returns {removed-id bed-ids}.
proc makeBed {} {
    sim new
    material add glass -density 2500 -young 1e7 -poisson 0.25 -restitution 0.5 -friction 0.4
    wall add plane -normal {0 0 1}
    wall add plane -normal {1 0 0}
    wall add plane -normal {-1 0 0} -point {0.04 0 0}
    wall add plane -normal {0 1 0}
    wall add plane -normal {0 -1 0} -point {0 0.04 0}
    set gone [element add -radius 0.001 -position {0.02 0.02 0.15}]
    element remove $gone
    set ids [pack random -region {box {0.001 0.001 0.001} {0.039 0.039 0.06}} \
        -radius {uniform 0.0014 0.002} -count 1200 -seed 7]
    behavior add gravity
    sim timestep 2e-5
    # Distributed runs give every element half the skin; alone, a fast element's margin may
    # widen (a thrown one): the serial run does as the ranks do, so both search at the same
    # steps (each search drops the contacts' damper losses still to book, 1e-6 of the damping).
    module set detection -margins 0
    return [list $gone $ids]
}
