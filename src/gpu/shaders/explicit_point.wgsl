// Where the explicit forces (adhesion, cohesion) and absorption's demands are taken
// (physics/bdf2.rs `explicit_point`): BDF2 at x0 + h v0, the step's end to O(h^2) (at x0 they
// would pump any oscillation they drive); the other integrators at x0. One snippet for the
// hair modules, which pull and ask there, and the held-water module, whose absorb pass
// recomputes each ask at the same point.
fn explicit_point(st: State) -> vec3<f32> {
    if (BDF2) {
        return st.x.xyz + P.h * st.v.xyz;
    }
    return st.x.xyz;
}
