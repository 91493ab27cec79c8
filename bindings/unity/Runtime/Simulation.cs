// The managed API over the C ABI: a Groom and a Simulation that own their native objects
// (SafeHandle), throw WetHairException on failure, and copy vertices once, straight into the
// caller's array, Span or (in Unity) NativeArray.
using System;
using System.Runtime.InteropServices;
#if UNITY_2021_3_OR_NEWER
using Unity.Collections;
using Unity.Collections.LowLevel.Unsafe;
#endif

namespace WetHair
{
    /// <summary>Strands: rest positions, pinned roots, masses.</summary>
    public sealed class Groom : IDisposable
    {
        internal readonly GroomHandle Handle;

        Groom(GroomHandle h) { Handle = h; }

        /// <summary>The paper's procedural scene.</summary>
        public static Groom PaperScene(uint strands, uint points)
        {
            WetHairException.Check(Native.wethair_groom_create_paper_scene(strands, points, out GroomHandle h));
            return new Groom(h);
        }

        /// <summary>A .tfx or .hair file, pointMass kg per point.</summary>
        public static Groom Load(string path, float pointMass)
        {
            WetHairException.Check(Native.wethair_groom_load(path, pointMass, out GroomHandle h));
            return new Groom(h);
        }

        /// <summary>The host's strands: pointCounts per strand, positions xyz per point (m),
        /// roots pinned (the first point of each strand).</summary>
        public static unsafe Groom FromStrands(uint[] pointCounts, float[] positions, float pointMass)
        {
            if (pointCounts == null || positions == null) throw new ArgumentNullException(pointCounts == null ? "pointCounts" : "positions");
            var desc = new WetHairGroomDesc();
            Native.wethair_groom_desc_default(&desc);
            fixed (uint* counts = pointCounts)
            fixed (float* pos = positions)
            {
                desc.strand_count = (uint)pointCounts.Length;
                desc.strand_point_counts = (IntPtr)counts;
                desc.positions = (IntPtr)pos;
                desc.point_count = (uint)(positions.Length / 3);
                desc.default_mass = pointMass;
                WetHairException.Check(Native.wethair_groom_create(&desc, out GroomHandle h));
                return new Groom(h);
            }
        }

        /// <summary>Strand and point counts.</summary>
        public (uint strands, uint points) Counts
        {
            get
            {
                WetHairException.Check(Native.wethair_groom_get_counts(Handle, out uint s, out uint p));
                return (s, p);
            }
        }

        public void Dispose() => Handle.Dispose();
    }

    /// <summary>One wet-hair simulation. Calls on one simulation must not overlap.</summary>
    public sealed unsafe class Simulation : IDisposable
    {
        readonly SimulationHandle handle;

        /// <summary>The paper scene's exact defaults (wethair_sim_desc_default).</summary>
        public static WetHairSimDesc DefaultDesc()
        {
            var d = new WetHairSimDesc();
            Native.wethair_sim_desc_default(&d);
            return d;
        }

        /// <summary>The current defaults, right for any groom: springs from material
        /// properties, the AUTO integrator (wethair_sim_desc_init).</summary>
        public static WetHairSimDesc GroomDesc()
        {
            var d = new WetHairSimDesc();
            Native.wethair_sim_desc_init(&d, (uint)sizeof(WetHairSimDesc));
            return d;
        }

        /// <summary>Creates a simulation of <paramref name="groom"/> (copied) with
        /// <paramref name="desc"/> and optional colliders (head space, or, with
        /// <paramref name="colliderFrames"/>, 16 column-major floats per collider, each in its
        /// own frame: SetColliderTransform moves them). With
        /// <paramref name="onUnityDevice"/>, through the Unity plugin: on Unity's own VkDevice
        /// when the plugin intercepted its creation, else as usual (UnityStatus says which).</summary>
        public Simulation(Groom groom, WetHairSimDesc desc, WetHairCollider[] colliders = null, bool onUnityDevice = false, float[] colliderFrames = null)
        {
            if (groom == null) throw new ArgumentNullException(nameof(groom));
            int n = colliders == null ? 0 : colliders.Length;
            if (colliderFrames != null && colliderFrames.Length != 16 * n)
                throw new ArgumentException("16 floats per collider expected", nameof(colliderFrames));
            bool added = false;
            groom.Handle.DangerousAddRef(ref added);
            try
            {
                fixed (WetHairCollider* c = colliders)
                fixed (float* frames = colliderFrames)
                {
                    desc.groom = groom.Handle.DangerousGetHandle();
                    desc.colliders = (IntPtr)c;
                    desc.collider_count = (uint)n;
                    desc.collider_frames = (IntPtr)frames;
                    WetHairException.Check(onUnityDevice
                        ? Native.wethair_unity_sim_create(&desc, out handle)
                        : Native.wethair_sim_create(&desc, out handle));
                }
            }
            finally
            {
                if (added) groom.Handle.DangerousRelease();
            }
        }

        /// <summary>The native handle (for the Unity render-thread plugin event).</summary>
        public SimulationHandle Handle => handle;

        /// <summary>Where the head is at the end of the next step: 16 floats, column-major
        /// (UnityEngine.Matrix4x4's element order).</summary>
        public void SetHeadTransform(float[] columnMajor4x4)
        {
            if (columnMajor4x4 == null || columnMajor4x4.Length != 16) throw new ArgumentException("16 floats expected", nameof(columnMajor4x4));
            fixed (float* m = columnMajor4x4) WetHairException.Check(Native.wethair_sim_set_head_transform(handle, m));
        }

        /// <summary>Where collider <paramref name="index"/>'s own frame is at the end of the
        /// next step (a simulation made with colliderFrames): 16 floats, column-major.</summary>
        public void SetColliderTransform(uint index, float[] columnMajor4x4)
        {
            if (columnMajor4x4 == null || columnMajor4x4.Length != 16) throw new ArgumentException("16 floats expected", nameof(columnMajor4x4));
            fixed (float* m = columnMajor4x4) WetHairException.Check(Native.wethair_sim_set_collider_transform(handle, index, m));
        }

        /// <summary>Where every strand's root is at the end of the next step (a simulation made
        /// with skinned_roots): xyz positions (m, world) and xyzw unit quaternions, one per strand
        /// (UnityEngine.Quaternion's order).</summary>
        public void SetRootFrames(ReadOnlySpan<float> positions, ReadOnlySpan<float> rotations)
        {
            if (positions.Length % 3 != 0 || rotations.Length != positions.Length / 3 * 4)
                throw new ArgumentException("xyz positions and xyzw rotations, one each per strand");
            fixed (float* p = &MemoryMarshal.GetReference(positions))
            fixed (float* q = &MemoryMarshal.GetReference(rotations))
                WetHairException.Check(Native.wethair_sim_set_root_frames(handle, p, q, (uint)(positions.Length / 3)));
        }

        /// <summary>Adds particles at rest: xyz positions (m, world).</summary>
        public void AddWater(ReadOnlySpan<float> positions) => AddWater(positions, ReadOnlySpan<float>.Empty);

        /// <summary>Adds particles: xyz positions (m, world) and xyz velocities (m/s; empty: at rest).</summary>
        public void AddWater(ReadOnlySpan<float> positions, ReadOnlySpan<float> velocities)
        {
            if (positions.Length % 3 != 0 || (velocities.Length != 0 && velocities.Length != positions.Length))
                throw new ArgumentException("positions and velocities must be xyz triples of equal count");
            if (positions.Length == 0) return;
            fixed (float* p = &MemoryMarshal.GetReference(positions))
            fixed (float* v = &MemoryMarshal.GetReference(velocities))
                WetHairException.Check(Native.wethair_sim_add_water(handle, p, velocities.Length == 0 ? null : v, (uint)(positions.Length / 3)));
        }

        /// <summary>Removes every particle.</summary>
        public void ClearWater() => WetHairException.Check(Native.wethair_sim_clear_water(handle));

        /// <summary>Advances by dt seconds.</summary>
        public void Step(float dt) => WetHairException.Check(Native.wethair_sim_step(handle, dt));

        /// <summary>Simulates the first <paramref name="fraction"/> of the guides from the next
        /// step on (a simulation made with guides), blending the output over guides.blend_time.</summary>
        public void SetGuideFraction(float fraction) => WetHairException.Check(Native.wethair_sim_set_guide_fraction(handle, fraction));

        /// <summary>Advances by a frame of <paramref name="frameTime"/> seconds in the desc's
        /// fixed steps (Time.deltaTime from Update: the same steps at any frame rate); without
        /// a fixed step, one step of the frame.</summary>
        public WetHairAdvance Advance(float frameTime)
        {
            var r = new WetHairAdvance { struct_size = (uint)sizeof(WetHairAdvance) };
            WetHairException.Check(Native.wethair_sim_advance(handle, frameTime, &r));
            return r;
        }

        /// <summary>Back to rest, dry, no water.</summary>
        public void Reset() => WetHairException.Check(Native.wethair_sim_reset(handle));

        /// <summary>Wets every hair point up to <paramref name="saturation"/> times its hold limit
        /// (its capacity and the water between its fibres; 0..10, above 1 the excess runs and
        /// drips), as after a dunk (needs held_water.enabled; wethair_sim_soak).</summary>
        public void Soak(float saturation) => WetHairException.Check(Native.wethair_sim_soak(handle, saturation));

        /// <summary>Sets the wind from the next step on (wethair_sim_set_wind).</summary>
        public void SetWind(WetHairWind wind) => WetHairException.Check(Native.wethair_sim_set_wind(handle, &wind));

        /// <summary>Sets the wind from its velocity (m/s), gust (0..1) and seed, for callers
        /// without unsafe code.</summary>
        public void SetWind(float vx, float vy, float vz, float gust, uint seed)
        {
            var wind = new WetHairWind { gust = gust, seed = seed };
            wind.velocity[0] = vx;
            wind.velocity[1] = vy;
            wind.velocity[2] = vz;
            SetWind(wind);
        }

        /// <summary>Vertex count, stride and attribute offsets.</summary>
        public WetHairVertexLayout Layout
        {
            get
            {
                var l = new WetHairVertexLayout { struct_size = (uint)sizeof(WetHairVertexLayout) };
                WetHairException.Check(Native.wethair_sim_get_vertex_layout(handle, &l));
                return l;
            }
        }

        /// <summary>Floats one vertex read writes (vertex_count * stride_floats).</summary>
        public int VertexFloats
        {
            get { var l = Layout; return (int)(l.vertex_count * l.stride_floats); }
        }

        /// <summary>Copies the vertices into <paramref name="dst"/> (at least VertexFloats long):
        /// one copy, from the library into the caller's memory. Returns the floats written.</summary>
        public int ReadVertices(Span<float> dst)
        {
            fixed (float* d = &MemoryMarshal.GetReference(dst))
            {
                WetHairException.Check(Native.wethair_sim_get_vertex_buffer(handle, d, (UIntPtr)dst.Length, out UIntPtr written));
                return (int)written.ToUInt64();
            }
        }

#if UNITY_2021_3_OR_NEWER
        /// <summary>Copies the vertices into a NativeArray (e.g. to fill a GraphicsBuffer with
        /// SetData without a managed copy).</summary>
        public int ReadVertices(NativeArray<float> dst)
        {
            WetHairException.Check(Native.wethair_sim_get_vertex_buffer(handle, (float*)dst.GetUnsafePtr(), (UIntPtr)dst.Length, out UIntPtr written));
            return (int)written.ToUInt64();
        }
#endif

        /// <summary>Counters and measures (the measures are taken now: a search over the
        /// strands, and on the GPU a read back). For every frame, read <see cref="Counters"/>.</summary>
        public WetHairStats Stats
        {
            get
            {
                var s = new WetHairStats { struct_size = (uint)sizeof(WetHairStats) };
                WetHairException.Check(Native.wethair_sim_get_stats(handle, &s));
                return s;
            }
        }

        /// <summary>The counters of <see cref="Stats"/> without its measures (those are -1):
        /// no search and no read of the positions, for every frame (on the GPU it waits for the
        /// last step).</summary>
        public WetHairStats Counters
        {
            get
            {
                var s = new WetHairStats { struct_size = (uint)sizeof(WetHairStats) };
                WetHairException.Check(Native.wethair_sim_get_counters(handle, &s));
                return s;
            }
        }

        /// <summary>"GPU on NVIDIA ..." or "CPU on CPU, 8 threads", with AUTO's reason.</summary>
        public string BackendDescription
        {
            get
            {
                var b = new WetHairBackendInfo { struct_size = (uint)sizeof(WetHairBackendInfo) };
                WetHairException.Check(Native.wethair_sim_get_backend_info(handle, &b));
                string device = Marshal.PtrToStringAnsi((IntPtr)b.device);
                string reason = Marshal.PtrToStringAnsi((IntPtr)b.fallback_reason);
                return ((Backend)b.backend == Backend.Gpu ? "GPU on " : "CPU on ") + device + (reason.Length > 0 ? " (" + reason + ")" : "");
            }
        }

        public void Dispose() => handle.Dispose();

        /// <summary>The Unity plugin's state: renderer, whether simulations go on Unity's
        /// device and why not, the render event id.</summary>
        public static WetHairUnityStatus UnityStatus
        {
            get
            {
                var st = new WetHairUnityStatus { struct_size = (uint)sizeof(WetHairUnityStatus) };
                WetHairException.Check(Native.wethair_unity_get_status(&st));
                return st;
            }
        }

        /// <summary>The plugin's render event (UnityRenderingEventAndData).</summary>
        public static IntPtr RenderEventFunc => Native.wethair_unity_get_render_event_func();
    }
}
