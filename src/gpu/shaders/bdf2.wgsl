// BDF2's start (physics/bdf2.rs `start_rows`, inside pass implicit_solve): each point's state
// blended with its state at the last substep's start, `a x0 - b x-1` written `x0 + b (x0 - x-1)`
// (a = 1 + b; the rounded a and b would not sum to 1 and drift the strands) and the same for
// velocities (S.blend = a, b, h, 1/h), which it then keeps for the next substep. With b = 0 (a
// restart) the state is as it is. The CPU keeps the displacement and the rounding from its f64
// solve instead of x-1 (`Bdf2Row`); this solve is f32, so x0 - x-1 is all there is to keep.

@group(2) @binding(1) var<storage, read_write> bdf2_history: array<State>;

fn start_of(idx: u32, st: State) -> State {
    let last = bdf2_history[idx];
    bdf2_history[idx] = st;
    if (S.blend.y == 0.0) {
        return st;
    }
    let b = S.blend.y;
    let x = st.x.xyz + b * (st.x.xyz - last.x.xyz);
    let v = st.v.xyz + b * (st.v.xyz - last.v.xyz);
    return State(vec4<f32>(x, st.x.w), vec4<f32>(v, 0.0));
}
