//! The plain-old-data records the GPU passes read, laid out exactly as the WGSL structs in
//! `shaders/common.wgsl` declare them, and the helpers that create buffers.

use bytemuck::{Pod, Zeroable};

/// Per-step constants (WGSL `Params`, a uniform).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Params {
    /// Substep, s.
    pub h: f32,
    /// 1 / substep, computed on the host as the CPU backend does.
    pub inv_h: f32,
    /// Air drag on hair, N·s/m.
    pub drag: f32,
    /// Collider friction.
    pub friction: f32,
    /// Gravity (xyz), m/s².
    pub g: [f32; 4],
    /// Hair points.
    pub points: u32,
    /// Strands.
    pub strands: u32,
    /// Stretch stiffness and damping.
    pub stretch_k: f32,
    /// Stretch damping.
    pub stretch_c: f32,
    /// Bend stiffness.
    pub bend_k: f32,
    /// Bend damping.
    pub bend_c: f32,
    /// Eq. 2's r_min.
    pub r_min: f32,
    /// Eq. 2's r_max.
    pub r_max: f32,
    /// Eq. 2's s.
    pub adhesion: f32,
    /// Wetting per substep, min(rate h, 1).
    pub wet_gain: f32,
    /// 1 / particle mass.
    pub particle_inv_mass: f32,
    /// Particle drag, N·s/m.
    pub water_drag: f32,
    /// Particle capacity.
    pub capacity: u32,
    /// Floats per vertex.
    pub stride: u32,
    /// Position offset in floats, or `u32::MAX`.
    pub pos_off: u32,
    /// Tangent offset, or `u32::MAX`.
    pub tan_off: u32,
    /// Wetness offset, or `u32::MAX`.
    pub wet_off: u32,
    /// Particles waiting in the incoming buffer.
    pub incoming: u32,
    /// Most grid cells.
    pub max_cells: u32,
    /// Squared domain radius, m².
    pub domain_r2: f32,
    /// Domain centre (xyz), placed by this step's final head transform.
    pub domain_center: [f32; 4],
}

/// Constant data of one hair point (WGSL `Point`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct PointGpu {
    /// Rest position in head space.
    pub rest: [f32; 3],
    /// 1 / mass, 0 when pinned.
    pub inv_mass: f32,
    /// Rest length to the next point.
    pub rest_stretch: f32,
    /// Rest length to the point after next.
    pub rest_bend: f32,
    /// The strand's first point.
    pub first: u32,
    /// The strand's last point.
    pub last: u32,
}

/// Dynamic state of one hair point or particle (WGSL `State` / `Particle`): x (w = wetness)
/// and v.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct StateGpu {
    /// Position; w is the wetness (hair) or unused (water).
    pub x: [f32; 4],
    /// Velocity; w unused.
    pub v: [f32; 4],
}

/// A collider placed for one substep (WGSL `Collider`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ColliderGpu {
    /// Axis start (xyz) and radius (w).
    pub a: [f32; 4],
    /// Axis (xyz) and 1 / |axis|² (w).
    pub ab: [f32; 4],
}

/// Workgroup size of the per-point and per-particle passes.
pub const WG: u32 = 64;
/// Workgroups per row of a 2D dispatch.
pub const MAX_GROUPS_X: u32 = 65_535;

/// Workgroup counts (x, y) that cover `n` invocations of [`WG`].
pub fn groups(n: u32) -> (u32, u32) {
    let g = n.div_ceil(WG).max(1);
    if g <= MAX_GROUPS_X {
        (g, 1)
    } else {
        (MAX_GROUPS_X, g.div_ceil(MAX_GROUPS_X))
    }
}

/// A buffer of `size` bytes (at least 16) with `usage`.
pub fn buffer(dev: &wgpu::Device, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    dev.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16).next_multiple_of(16),
        usage,
        mapped_at_creation: false,
    })
}

/// Storage usage that the host may also write and copy from.
pub const STORAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE
    .union(wgpu::BufferUsages::COPY_DST)
    .union(wgpu::BufferUsages::COPY_SRC);
