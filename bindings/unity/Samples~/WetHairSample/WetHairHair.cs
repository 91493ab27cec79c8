// Sample: wet hair on a GameObject. Creates a simulation from a hair file (.tfx or .hair, in
// StreamingAssets) or the paper scene, follows this transform as the head, sprays water while
// a key is held, soaks the hair and toggles a gusty wind on keys (the full wet model: held
// water that weighs, bridges, drips and dries; CPU backend for now), steps on the render thread through the plugin event, and fills a
// GraphicsBuffer with the vertices (copy path) for a material to draw with
// Graphics.RenderPrimitivesIndexed (see bindings/shaders/kajiya_kay.hlsl for the shading).
//
// Not compiled or run here (it needs UnityEngine); the bindings it uses are, by mono.
using System;
using System.Runtime.InteropServices;
using Unity.Collections;
using UnityEngine;
using UnityEngine.Rendering;
using WetHair;

public class WetHairHair : MonoBehaviour
{
    [Tooltip("A .tfx or .hair file under StreamingAssets; empty: the paper scene.")]
    public string hairFile = "";
    [Tooltip("Mass of one hair point, kg (groom files carry none).")]
    public float pointMass = 1e-3f;
    [Tooltip("Held to spray water from the camera.")]
    public KeyCode sprayKey = KeyCode.Space;
    public int particlesPerFrame = 50;
    [Tooltip("The full wet model (held water, liquid bridges, drip, drying); off: the paper's adhesion only.")]
    public bool fullWetModel = true;
    [Tooltip("Soaks the hair to saturation (full wet model).")]
    public KeyCode soakKey = KeyCode.S;
    [Tooltip("Toggles the wind.")]
    public KeyCode windKey = KeyCode.W;
    public Vector3 windVelocity = new Vector3(3f, 0f, 0f);
    [Range(0f, 1f)] public float windGust = 0.5f;
    public Material hairMaterial;
    bool windOn;

    Groom groom;
    Simulation sim;
    GraphicsBuffer vertices, indices;
    NativeArray<float> staging;
    IntPtr renderEvent;
    int eventBase;
    // Pinned for the render thread: Unity passes its address to the plugin event.
    GCHandle stepHandle;
    WetHairUnityStep[] step = new WetHairUnityStep[1];
    CommandBuffer commands;
    System.Random rng = new System.Random(1);

    void OnEnable()
    {
        groom = string.IsNullOrEmpty(hairFile)
            ? Groom.PaperScene(10000, 6)
            : Groom.Load(System.IO.Path.Combine(Application.streamingAssetsPath, hairFile), pointMass);
        // The current layout (it has held_water and wind); the paper scene keeps its own springs.
        var desc = Simulation.GroomDesc();
        if (string.IsNullOrEmpty(hairFile))
        {
            desc.spring_model = 0; // per spring, the paper's constants
            desc.integrator = (uint)Integrator.SymplecticEuler;
            // Its points weigh 1 g (wisps of thousands of hairs): a thirtieth of the default
            // capacity, a fiftieth of the water between fibres, 30 mg drops (as the main job's
            // strip does).
            desc.held_water.capacity_ratio = 0.01f;
            desc.held_water_free_ratio = 0.02f;
            desc.held_water.drip_mass = 3e-5f;
            // The paper's drag and pull on every point alike, as the main job runs it.
            desc.air_drag_length = 0f;
            desc.water_adhesion_length = 0f;
        }
        desc.backend = (uint)Backend.Auto;
        // So the wind moves the hair, not only the water: per 2 cm of a loaded groom's hair
        // (init's air_drag_length), so the same however finely the file samples it.
        desc.air_drag = 0.002f;
        desc.held_water.enabled = fullWetModel ? 1u : 0u;
        // On Unity's Vulkan renderer this runs on Unity's own VkDevice (see the README).
        sim = new Simulation(groom, desc, new[] { new WetHairCollider { shape = 0, radius = 0.1f } }, onUnityDevice: true);
        Debug.Log("wethair: " + sim.BackendDescription);

        var layout = sim.Layout;
        staging = new NativeArray<float>((int)(layout.vertex_count * layout.stride_floats), Allocator.Persistent);
        vertices = new GraphicsBuffer(GraphicsBuffer.Target.Structured, (int)layout.vertex_count, (int)layout.stride_floats * 4);
        uint per = layout.vertex_count / layout.strand_count;
        var idx = new int[layout.strand_count * (per - 1) * 2];
        for (uint s = 0, k = 0; s < layout.strand_count; s++)
            for (uint i = 0; i + 1 < per; i++) { idx[k++] = (int)(s * per + i); idx[k++] = (int)(s * per + i + 1); }
        indices = new GraphicsBuffer(GraphicsBuffer.Target.Index, idx.Length, 4);
        indices.SetData(idx);

        renderEvent = Simulation.RenderEventFunc;
        eventBase = Simulation.UnityStatus.event_id_base;
        stepHandle = GCHandle.Alloc(step, GCHandleType.Pinned);
        commands = new CommandBuffer { name = "wethair step" };
    }

    void Update()
    {
        // The head follows this transform (column-major, as Matrix4x4 stores it).
        var m = transform.localToWorldMatrix;
        var cols = new float[16];
        for (int i = 0; i < 16; i++) cols[i] = m[i];
        sim.SetHeadTransform(cols);

        if (Input.GetKey(sprayKey)) Spray();
        if (fullWetModel && Input.GetKeyDown(soakKey)) sim.Soak(1.0f);
        if (Input.GetKeyDown(windKey))
        {
            windOn = !windOn;
            var v = windOn ? windVelocity : Vector3.zero;
            sim.SetWind(v.x, v.y, v.z, windOn ? windGust : 0f, 1);
        }

        // Read last frame's step result (the render thread wrote it), then step this frame there.
        if (step[0].result != 0 && step[0].struct_size != 0)
            Debug.LogWarning("wethair step failed: " + (Result)step[0].result);
        step[0] = new WetHairUnityStep { struct_size = (uint)Marshal.SizeOf<WetHairUnityStep>(), dt = Time.deltaTime, sim = sim.Handle.DangerousGetHandle() };
        commands.Clear();
        commands.IssuePluginEventAndData(renderEvent, eventBase, stepHandle.AddrOfPinnedObject());
        Graphics.ExecuteCommandBuffer(commands);

        // Copy path: one copy from the library into the NativeArray, one upload.
        sim.ReadVertices(staging);
        vertices.SetData(staging);
        if (hairMaterial != null)
        {
            hairMaterial.SetBuffer("_Vertices", vertices);
            var rp = new RenderParams(hairMaterial) { worldBounds = new Bounds(transform.position, Vector3.one * 2) };
            Graphics.RenderPrimitivesIndexed(rp, MeshTopology.Lines, indices, indices.count);
        }
    }

    void Spray()
    {
        var cam = Camera.main;
        if (cam == null) return;
        var ray = cam.ScreenPointToRay(Input.mousePosition);
        var pos = new float[3 * particlesPerFrame];
        var vel = new float[3 * particlesPerFrame];
        for (int i = 0; i < particlesPerFrame; i++)
        {
            Vector3 d = (ray.direction + 0.05f * UnityEngine.Random.insideUnitSphere).normalized;
            Vector3 p = ray.origin + d * 0.1f;
            pos[3 * i] = p.x; pos[3 * i + 1] = p.y; pos[3 * i + 2] = p.z;
            vel[3 * i] = 3 * d.x; vel[3 * i + 1] = 3 * d.y; vel[3 * i + 2] = 3 * d.z;
        }
        sim.AddWater(pos, vel);
    }

    void OnDisable()
    {
        // The render thread may still hold this frame's event: finish it before freeing.
        GL.Flush();
        commands?.Release();
        if (stepHandle.IsAllocated) stepHandle.Free();
        vertices?.Release();
        indices?.Release();
        if (staging.IsCreated) staging.Dispose();
        sim?.Dispose();
        groom?.Dispose();
    }
}
