// A console program that drives the real library through the Unity package's bindings, built
// with mono's C# compiler in the tests (no Unity needed):
//   mono drive.exe           create, add water, step, read vertices, the documented exception
//   mono drive.exe --layout  every binding struct's size and field offsets, for comparison
//                            with the C header's (scripts/test.sh compiles the C side)
using System;
using System.Reflection;
using System.Runtime.InteropServices;
using WetHair;

static class Drive
{
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    delegate void RenderEvent(int eventId, ref WetHairUnityStep step);

    static int Fail(string what)
    {
        Console.Error.WriteLine("FAILED: " + what);
        return 1;
    }

    static int Layout()
    {
        foreach (Type t in typeof(Native).Assembly.GetTypes())
        {
            if (!t.IsValueType || t.IsEnum || !t.Name.StartsWith("WetHair")) continue;
            Console.WriteLine("size " + t.Name + " " + Marshal.SizeOf(t));
            foreach (FieldInfo f in t.GetFields(BindingFlags.Public | BindingFlags.Instance))
                Console.WriteLine("offset " + t.Name + " " + f.Name + " " + Marshal.OffsetOf(t, f.Name));
        }
        return 0;
    }

    static unsafe int Main(string[] args)
    {
        if (args.Length > 0 && args[0] == "--layout") return Layout();
        Console.WriteLine("wethair " + Marshal.PtrToStringAnsi(Native.wethair_version_string()) + " through the C# bindings");
        using (Groom groom = Groom.PaperScene(2000, 6))
        {
            var desc = Simulation.DefaultDesc();
            desc.backend = (uint)Backend.Cpu;
            var head = new WetHairCollider { shape = (uint)ColliderShape.Sphere, radius = 0.1f };
            using (var sim = new Simulation(groom, desc, new[] { head }))
            {
                Console.WriteLine("backend: " + sim.BackendDescription);
                var pos = new float[3 * 200];
                var vel = new float[3 * 200];
                var rnd = new Random(7);
                for (int i = 0; i < 200; i++)
                {
                    double r = 0.12 * Math.Sqrt(rnd.NextDouble()), th = 2 * Math.PI * rnd.NextDouble();
                    pos[3 * i] = (float)(r * Math.Cos(th));
                    pos[3 * i + 1] = (float)(r * Math.Sin(th));
                    pos[3 * i + 2] = 0.3f;
                    vel[3 * i + 2] = -1.0f;
                }
                sim.AddWater(pos, vel);
                for (int f = 0; f < 30; f++) sim.Step(1.0f / 60.0f);
                var layout = sim.Layout;
                var verts = new float[sim.VertexFloats];
                int written = sim.ReadVertices(verts);
                if (written != verts.Length || layout.vertex_count != 12000) return Fail("vertex count " + written);
                foreach (float v in verts)
                    if (float.IsNaN(v) || float.IsInfinity(v)) return Fail("non-finite vertex");
                var st = sim.Stats;
                Console.WriteLine("stepped 30 frames: " + st.points + " points, " + st.particles + " particles held, clumping " + st.clumping.ToString("F5") + " m, " + written + " floats read");
                if (st.steps != 30) return Fail("steps " + st.steps);
                var counters = sim.Counters;
                if (counters.steps != 30 || counters.particles != st.particles || counters.clumping != -1.0f)
                    return Fail("counters: steps " + counters.steps + ", clumping " + counters.clumping);

                // The error path: a NaN dt raises WetHairException(InvalidArgument).
                try
                {
                    sim.Step(float.NaN);
                    return Fail("a NaN dt did not throw");
                }
                catch (WetHairException e)
                {
                    if (e.Code != Result.InvalidArgument) return Fail("code " + e.Code);
                    Console.WriteLine("threw as documented: " + e.Message);
                }
                // A too-small destination raises BufferTooSmall and writes nothing.
                var small = new float[8];
                for (int i = 0; i < small.Length; i++) small[i] = 42.0f;
                try
                {
                    sim.ReadVertices(small);
                    return Fail("a short buffer did not throw");
                }
                catch (WetHairException e)
                {
                    if (e.Code != Result.BufferTooSmall) return Fail("code " + e.Code);
                    foreach (float v in small)
                        if (v != 42.0f) return Fail("a failed read wrote into the buffer");
                    Console.WriteLine("threw as documented: " + e.Message);
                }
            }
        }
        // Fixed steps (0.4.0): a 50 Hz Update's Advance takes 2 steps of 1/120 s and blends
        // 0.4 of the next; 30 frames of 1/30 s and 144 frames of 1/144 s both take 120.
        using (Groom gf = Groom.PaperScene(100, 6))
        {
            var desc = Simulation.GroomDesc();
            desc.backend = (uint)Backend.Cpu;
            desc.fixed_step = 1.0f / 120.0f;
            using (var sim = new Simulation(gf, desc, new WetHairCollider[0]))
            {
                var a = sim.Advance(1.0f / 50.0f);
                if (a.steps != 2 || Math.Abs(a.blend - 0.4f) > 1e-4f) return Fail("advance " + a.steps + " " + a.blend);
                sim.Reset();
                uint n = 0;
                for (int f = 0; f < 144; f++) n += sim.Advance(1.0f / 144.0f).steps;
                if (n != 120) return Fail("144 Hz took " + n + " steps");
                Console.WriteLine("fixed steps: 2 steps and a 0.4 blend at 50 Hz, 120 steps a second at 144 Hz");
            }
        }
        // Colliders on bones (0.10.0): a sphere in its own frame, moved each step; an index
        // past the colliders throws InvalidArgument, and a simulation whose colliders follow
        // the head throws Unsupported.
        using (Groom gb = Groom.PaperScene(100, 6))
        {
            var desc = Simulation.GroomDesc();
            desc.backend = (uint)Backend.Cpu;
            var ball = new WetHairCollider { shape = (uint)ColliderShape.Sphere, radius = 0.04f };
            var frame = new float[16];
            frame[0] = frame[5] = frame[10] = frame[15] = 1.0f;
            frame[12] = 0.3f;
            using (var sim = new Simulation(gb, desc, new[] { ball }, false, frame))
            {
                for (int f = 0; f < 10; f++)
                {
                    frame[12] = 0.3f - 0.02f * f;
                    sim.SetColliderTransform(0, frame);
                    sim.Step(1.0f / 60.0f);
                }
                var verts = new float[sim.VertexFloats];
                sim.ReadVertices(verts);
                foreach (float v in verts)
                    if (float.IsNaN(v) || float.IsInfinity(v)) return Fail("non-finite vertex with a moving collider");
                try
                {
                    sim.SetColliderTransform(1, frame);
                    return Fail("collider 1 of 1 was taken");
                }
                catch (WetHairException e)
                {
                    if (e.Code != Result.InvalidArgument) return Fail("code " + e.Code);
                }
            }
            using (var sim = new Simulation(gb, desc, new[] { ball }))
            {
                try
                {
                    sim.SetColliderTransform(0, frame);
                    return Fail("a head collider took a frame");
                }
                catch (WetHairException e)
                {
                    if (e.Code != Result.Unsupported) return Fail("code " + e.Code);
                    Console.WriteLine("collider frames: moved for 10 steps; refusals threw: " + e.Message);
                }
            }
        }
        // Skinned roots (0.4.0): frames for every strand are taken; a count that is not the
        // strand count is refused with InvalidArgument.
        using (Groom gr = Groom.PaperScene(10, 6))
        {
            var desc = Simulation.GroomDesc();
            desc.backend = (uint)Backend.Cpu;
            desc.skinned_roots = 1;
            using (var sim = new Simulation(gr, desc, new WetHairCollider[0]))
            {
                var pos = new float[30];
                var rot = new float[40];
                for (int s = 0; s < 10; s++) { pos[3 * s + 2] = 0.1f; rot[4 * s + 3] = 1.0f; }
                sim.SetRootFrames(pos, rot);
                sim.Step(1.0f / 60.0f);
                try
                {
                    sim.SetRootFrames(new ReadOnlySpan<float>(pos, 0, 27), new ReadOnlySpan<float>(rot, 0, 36));
                    return Fail("9 frames for 10 strands were taken");
                }
                catch (WetHairException e)
                {
                    if (e.Code != Result.InvalidArgument) return Fail("code " + e.Code);
                    Console.WriteLine("skinned roots: frames taken; a short array threw: " + e.Message);
                }
            }
        }
        // The wet model through the current layout: soak, a gusty wind, drying; the ledger in
        // the stats balances to the quantum, and a bad saturation is refused.
        using (Groom g3 = Groom.PaperScene(500, 6))
        {
            var d3 = Simulation.GroomDesc();
            d3.backend = (uint)Backend.Cpu;
            d3.held_water.enabled = 1;
            d3.held_water.dry_time = 1.0f;
            d3.air_drag = 0.002f;
            using (var s3 = new Simulation(g3, d3))
            {
                s3.Soak(1.0f);
                s3.SetWind(2.0f, 0.0f, 0.0f, 0.5f, 3);
                for (int f = 0; f < 60; f++) s3.Step(1.0f / 60.0f);
                var w = s3.Stats;
                Console.WriteLine("wet model: added " + w.water_added + " quanta = particles " + w.water_in_particles + " + held " + w.water_held + " + left " + w.water_left + " + evaporated " + w.water_evaporated);
                if (w.water_added == 0 || w.water_held == 0 || w.water_evaporated == 0) return Fail("the hair did not soak and dry");
                if (w.water_added != w.water_in_particles + w.water_held + w.water_left + w.water_evaporated) return Fail("the ledger does not balance");
                try
                {
                    s3.Soak(float.NaN);
                    return Fail("a NaN saturation was accepted");
                }
                catch (WetHairException e)
                {
                    if (e.Code != Result.InvalidArgument) return Fail("code " + e.Code);
                }
            }
        }
        // The Unity entry outside Unity: not loaded, so simulations are made as usual.
        var us = Simulation.UnityStatus;
        if (us.loaded != 0) return Fail("plugin reported loaded outside Unity");
        using (Groom g2 = Groom.PaperScene(100, 6))
        {
            var d2 = Simulation.DefaultDesc();
            d2.backend = (uint)Backend.Cpu;
            using (var s2 = new Simulation(g2, d2, null, onUnityDevice: true))
            {
                var step = new WetHairUnityStep { struct_size = (uint)Marshal.SizeOf(typeof(WetHairUnityStep)), dt = 1.0f / 60.0f, sim = s2.Handle.DangerousGetHandle(), result = 99 };
                var ev = (RenderEvent)Marshal.GetDelegateForFunctionPointer(Simulation.RenderEventFunc, typeof(RenderEvent));
                ev(us.event_id_base, ref step);
                if (step.result != 0 || s2.Stats.steps != 1) return Fail("render event step: result " + step.result);
                Console.WriteLine("render event stepped a simulation made through the Unity entry");
            }
        }
        // A handle that was never made (null groom) is refused before reaching C.
        try
        {
            new Simulation(null, Simulation.DefaultDesc());
            return Fail("null groom accepted");
        }
        catch (ArgumentNullException) { }
        Console.WriteLine("C# bindings: OK");
        return 0;
    }
}
