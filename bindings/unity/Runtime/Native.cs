// P/Invoke declarations and blittable structs mirroring include/wethair.h, field for field
// (names as in C, so the layout check can compare them: bindings/unity/Tests~/Drive.cs).
using System;
using System.Runtime.InteropServices;

namespace WetHair
{
    /// <summary>Result codes of every fallible call (WetHairResult).</summary>
    public enum Result : uint
    {
        Ok = 0,
        NullPointer = 1,
        InvalidArgument = 2,
        StructSize = 3,
        Capacity = 4,
        BufferTooSmall = 5,
        Io = 6,
        Parse = 7,
        Unstable = 8,
        Panic = 9,
        Device = 10,
        Unsupported = 11,
    }

    /// <summary>Where the step runs (WetHairBackend).</summary>
    public enum Backend : uint { Auto = 0, Cpu = 1, Gpu = 2 }

    /// <summary>How each substep advances the strands (WetHairIntegrator).</summary>
    public enum Integrator : uint { SymplecticEuler = 0, ImplicitEuler = 1, Xpbd = 2, Auto = 3 }

    /// <summary>Collider shapes (WetHairColliderType).</summary>
    public enum ColliderShape : uint { Sphere = 0, Capsule = 1 }

    /// <summary>A spring's stiffness (N/m) and damping (N s/m).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairSpring
    {
        public float stiffness;
        public float damping;
    }

    /// <summary>Material properties (WETHAIR_SPRING_MODEL_MATERIAL): EA (N), its damping (N s),
    /// EI (N m^2), its damping (N m^2 s); each spring's k and c follow from its rest length.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairMaterial
    {
        public float stretch_modulus;
        public float stretch_damping;
        public float bend_modulus;
        public float bend_damping;
    }

    /// <summary>The wet model (since 0.2.0; units and defaults in the C header): water held by
    /// the hair, its weight, limpness, absorption, bridges, flow, drip and drying. Off when
    /// enabled is 0; CPU backend only for now.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairHeldWater
    {
        public uint enabled;
        public float capacity_ratio;
        public float dry_time;
        public float dry_air_speed;
        public float absorb_rate;
        public float wet_bend_ratio;
        public float bridge_tension;
        public float bridge_length;
        public float flow_mobility;
        public float drip_mass;
    }

    /// <summary>A uniform wind with gusts (since 0.2.0): velocity m/s, gust 0..1, seed.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public unsafe struct WetHairWind
    {
        public fixed float velocity[3];
        public float gust;
        public uint seed;
    }

    /// <summary>Water parameters (see the C header for units).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairWaterDesc
    {
        public float r_min;
        public float r_max;
        public float adhesion;
        public float particle_mass;
        public float drag;
        public uint capacity;
        public float wetting_rate;
        public float domain_radius;
    }

    /// <summary>A sphere (a, radius) or capsule (a to b, radius) in head space.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public unsafe struct WetHairCollider
    {
        public uint shape;
        public fixed float a[3];
        public fixed float b[3];
        public float radius;
    }

    /// <summary>The host's own strands.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairGroomDesc
    {
        public uint struct_size;
        public uint strand_count;
        public IntPtr strand_point_counts;
        public IntPtr positions;
        public uint point_count;
        public IntPtr pinned;
        public IntPtr masses;
        public float default_mass;
    }

    /// <summary>A simulation's description; start from Native.wethair_sim_desc_default.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public unsafe struct WetHairSimDesc
    {
        public uint struct_size;
        public uint damping_model;
        public IntPtr groom;
        public WetHairSpring stretch;
        public WetHairSpring bend;
        public fixed float gravity[3];
        public float air_drag;
        public uint substeps;
        public uint integrator;
        public uint solver_iterations;
        public uint threads;
        public WetHairWaterDesc water;
        public IntPtr colliders;
        public uint collider_count;
        public float friction;
        public uint vertex_attributes;
        public uint backend;
        public uint readback;
        public uint reserved;
        public uint spring_model;
        public WetHairMaterial material;
        public uint reserved2;
        /// <summary>Since 0.2.0: the wet model (off by default).</summary>
        public WetHairHeldWater held_water;
        /// <summary>Since 0.2.0: the wind at the start (calm by default).</summary>
        public WetHairWind wind;
        public uint reserved3;
        /// <summary>Since 0.3.0: the live error estimate, every N-th strand shadowed (0: off).</summary>
        public uint error_estimate_stride;
        /// <summary>Since 0.3.0: the error budget, m (0: off); the substeps follow it up to
        /// max_substeps.</summary>
        public float tolerance;
        public uint max_substeps;
        public uint reserved4;
        /// <summary>Since 0.4.0: fixed-step updates for wethair_sim_advance, s (0: off).</summary>
        public float fixed_step;
        /// <summary>Since 0.4.0: the longest frame one advance simulates, s (default 0.25).</summary>
        public float max_frame_time;
        /// <summary>Since 0.4.0: 1 (default) shows the state between the last two fixed steps.</summary>
        public uint interpolate;
        public uint reserved5;
        /// <summary>Since 0.4.0: SDF colliders (WetHairSdf array, both backends), and their count.</summary>
        public IntPtr sdfs;
        public uint sdf_count;
        public uint reserved6;
        /// <summary>Since 0.4.0: 1 roots follow wethair_sim_set_root_frames (a skinned mesh), 0 the head.</summary>
        public uint skinned_roots;
        /// <summary>Since 0.4.0: a root moving farther in one step teleports its strand, m (0: never).</summary>
        public float root_teleport_distance;
        /// <summary>Since 0.4.0: hair-hair volume (off by default).</summary>
        public WetHairVolume volume;
        /// <summary>Since 0.5.0: guides and followers with level of detail (off by default).</summary>
        public WetHairGuides guides;
        /// <summary>Since 0.6.0: water a kilogram of dry hair holds between its fibres against
        /// gravity, above held_water.capacity_ratio, kg/kg (default 1); only water above both runs
        /// and drips.</summary>
        public float held_water_free_ratio;
        public uint reserved7;
        /// <summary>Length of hair held_water.flow_mobility is quoted over, m (default 0.02):
        /// water runs down a strand at flow_mobility times it, m/s, however finely the strand
        /// is sampled.</summary>
        public float held_water_flow_length;
        public uint reserved8;
        /// <summary>Length of hair air_drag is quoted over, m (init's default 0.02; 0: every
        /// point takes air_drag, as before 0.8.0): a strand feels the same drag in a wind
        /// however finely it is sampled.</summary>
        public float air_drag_length;
        public uint reserved9;
        /// <summary>Length of hair water.adhesion is quoted over, m (init's default 0.02; 0:
        /// every point pulls with adhesion, as before 0.8.0): a drop pulls a strand alike
        /// however finely it is sampled.</summary>
        public float water_adhesion_length;
        public uint reserved10;
        /// <summary>Since 0.9.0: drops that meet coalesce, m (0, the default: they pass
        /// through each other): drops in one cell of this side take their mean position and
        /// velocity and pull as one. At most (r_max - r_min) / 8; the paper's model and the
        /// CPU backend only for now.</summary>
        public float water_pile_cell;
        public uint reserved11;
        /// <summary>Since 0.10.0: colliders on bones of their own (IntPtr.Zero, the default:
        /// every collider follows the head). Else collider_count column-major 4x4 matrices,
        /// 16 floats each: each collider's frame to the world at the start (rotation,
        /// translation, uniform scale); its points are in that frame, and
        /// wethair_sim_set_collider_transform moves it each step.</summary>
        public IntPtr collider_frames;
    }

    /// <summary>Which strands are guides (WetHairGuideChoice).</summary>
    public enum GuideChoice : uint { All = 0, EveryNth = 1, Spread = 2, Given = 3, Cluster = 4 }

    /// <summary>Since 0.5.0: guides and followers (docs/GUIDES.md): only the guides are
    /// simulated; every strand is written, followers from their nearest guides.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairGuides
    {
        /// <summary>A GuideChoice.</summary>
        public uint choice;
        /// <summary>n of every n-th, the spread count, or the length of strands.</summary>
        public uint count;
        /// <summary>The given guides' strand indices (uint array), or IntPtr.Zero.</summary>
        public IntPtr strands;
        /// <summary>Guides per follower: 1 or 3.</summary>
        public uint per_follower;
        /// <summary>How far a wet follower closes on its nearest guide, 0..1.</summary>
        public float clump;
        /// <summary>The fraction of the guides simulated at create, (0, 1].</summary>
        public float fraction;
        /// <summary>Seconds a change of the fraction blends over.</summary>
        public float blend_time;
    }

    /// <summary>Since 0.4.0: hair-hair volume (density pressure and friction over a grid).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairVolume
    {
        public uint enabled;
        public float cell;
        public float pressure;
        public float friction;
        public float rest_density;
        public uint reserved;
    }

    /// <summary>Since 0.4.0: a signed distance field collider (distances in m, x fastest,
    /// negative inside), placed by a column-major transform.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public unsafe struct WetHairSdf
    {
        public fixed uint dims[3];
        public fixed float origin[3];
        public float cell_size;
        public uint reserved;
        public IntPtr values;
        public fixed float transform[16];
    }

    /// <summary>Since 0.4.0: what one wethair_sim_advance did.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairAdvance
    {
        public uint struct_size;
        public uint steps;
        public float blend;
        public float dropped_time;
    }

    /// <summary>The vertex buffer's layout (byte offsets, -1 when absent).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairVertexLayout
    {
        public uint struct_size;
        public uint vertex_count;
        public uint strand_count;
        public uint stride_floats;
        public int position_offset;
        public int tangent_offset;
        public int wetness_offset;
    }

    /// <summary>Counters and measures of a simulation.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairStats
    {
        public uint struct_size;
        public uint strands;
        public uint points;
        public uint particles;
        public ulong particles_removed;
        public ulong steps;
        public float last_step_ms;
        public float max_speed;
        public float clumping;
        public uint threads;
        public uint integrator;
        public uint backend;
        /// <summary>Since 0.2.0: clumping along the strands' quarter points, m.</summary>
        public float clumping_along;
        /// <summary>Since 0.2.0, with held water: the exact water ledger in units of 1e-12 kg
        /// (added = in particles + held + left + evaporated).</summary>
        public ulong water_added;
        public ulong water_in_particles;
        public ulong water_held;
        public ulong water_left;
        public ulong water_evaporated;
        /// <summary>Since 0.3.0: the estimated position error, m, RMS and largest over the
        /// sampled strands (-1 when off or withheld).</summary>
        public float error_estimate;
        public float error_estimate_max;
        /// <summary>Since 0.3.0: the substeps the last step ran.</summary>
        public uint substeps;
        public uint reserved;
    }

    /// <summary>Which backend runs the simulation, its device, and why AUTO chose it.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public unsafe struct WetHairBackendInfo
    {
        public uint struct_size;
        public uint backend;
        public fixed byte device[128];
        public fixed byte fallback_reason[256];
    }

    /// <summary>The shared vertex VkBuffer and its synchronisation (see the C header).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairVulkanBuffer
    {
        public uint struct_size;
        public uint vertex_count;
        public ulong buffer;
        public ulong offset;
        public ulong size;
        public uint stride_bytes;
        public uint strand_count;
        public int position_offset;
        public uint position_format;
        public int tangent_offset;
        public uint tangent_format;
        public int wetness_offset;
        public uint wetness_format;
        public ulong ready_semaphore;
        public ulong ready_value;
        public ulong release_semaphore;
        public ulong release_value;
    }

    /// <summary>The water's shared positions and indirect-draw VkBuffers (see the C header).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairVulkanWater
    {
        public uint struct_size;
        public uint capacity;
        public ulong buffer;
        public ulong offset;
        public uint stride_bytes;
        public uint position_format;
        public ulong draw_buffer;
        public ulong draw_offset;
    }

    /// <summary>The Unity plugin's state (wethair_unity_get_status).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public unsafe struct WetHairUnityStatus
    {
        public uint struct_size;
        public uint loaded;
        public int renderer;
        public uint on_unity_device;
        public int event_id_base;
        public uint reserved;
        public fixed byte reason[256];
    }

    /// <summary>One render-thread step: pass its pinned address with event_id_base to
    /// CommandBuffer.IssuePluginEventAndData; the event writes result.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct WetHairUnityStep
    {
        public uint struct_size;
        public float dt;
        public IntPtr sim;
        public uint result;
        public uint reserved;
    }

    /// <summary>The C functions, one to one.</summary>
    public static unsafe class Native
    {
        const string Lib = "wethair";

        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern uint wethair_version();
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern IntPtr wethair_version_string();
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern IntPtr wethair_result_string(uint result);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern IntPtr wethair_last_error_message();
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern void wethair_sim_desc_default(WetHairSimDesc* desc);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_desc_init(WetHairSimDesc* desc, uint struct_size);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_soak(SimulationHandle sim, float saturation);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_set_wind(SimulationHandle sim, WetHairWind* wind);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern void wethair_groom_desc_default(WetHairGroomDesc* desc);

        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_groom_create(WetHairGroomDesc* desc, out GroomHandle groom);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_groom_create_paper_scene(uint strands, uint points, out GroomHandle groom);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_groom_load([MarshalAs(UnmanagedType.LPUTF8Str)] string path, float pointMass, out GroomHandle groom);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_groom_get_counts(GroomHandle groom, out uint strands, out uint points);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern void wethair_groom_destroy(IntPtr groom);

        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_create(WetHairSimDesc* desc, out SimulationHandle sim);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern void wethair_sim_destroy(IntPtr sim);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_set_head_transform(SimulationHandle sim, float* matrix);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_add_water(SimulationHandle sim, float* positions, float* velocities, uint count);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_clear_water(SimulationHandle sim);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_step(SimulationHandle sim, float dt);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_set_sdf_transform(SimulationHandle sim, uint index, float* matrix);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_set_collider_transform(SimulationHandle sim, uint index, float* matrix);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_set_guide_fraction(SimulationHandle sim, float fraction);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_set_root_frames(SimulationHandle sim, float* positions, float* rotations, uint count);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_advance(SimulationHandle sim, float frameTime, WetHairAdvance* result);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_reset(SimulationHandle sim);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_get_vertex_layout(SimulationHandle sim, WetHairVertexLayout* layout);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_get_vertex_buffer(SimulationHandle sim, float* dst, UIntPtr capacity, out UIntPtr written);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_get_water(SimulationHandle sim, float* dst, uint capacity, out uint written);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_get_stats(SimulationHandle sim, WetHairStats* stats);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_get_counters(SimulationHandle sim, WetHairStats* stats);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_get_backend_info(SimulationHandle sim, WetHairBackendInfo* info);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_get_vulkan_buffer(SimulationHandle sim, WetHairVulkanBuffer* buffer);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_sim_get_vulkan_water(SimulationHandle sim, WetHairVulkanWater* water);

        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_unity_get_status(WetHairUnityStatus* status);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern Result wethair_unity_sim_create(WetHairSimDesc* desc, out SimulationHandle sim);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)] public static extern IntPtr wethair_unity_get_render_event_func();
    }
}
