// wethair.hpp: a header-only C++17 wrapper over the C API (wethair.h).
//
// - Owning handles (Groom, Simulation, VulkanRequirements) are move-only and free their C
//   object in the destructor.
// - Errors are exceptions: every failing call throws wethair::Error, which carries the C
//   result code (code()) and the library's message (what()). The C API writes no output on
//   failure, so an exception leaves the caller's buffers as they were.
// - Nothing here allocates per frame beyond what the caller asks for: vertices() fills a
//   caller-owned std::vector, resized once.
//
// Link with the C library as usual (pkg-config --cflags --libs wethair).
#ifndef WETHAIR_HPP
#define WETHAIR_HPP

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "wethair.h"

namespace wethair {

/// A failed call: the C result code and the library's message.
class Error : public std::runtime_error {
public:
    Error(WetHairResult code, const std::string &message) : std::runtime_error(message), code_(code) {}
    /// The WETHAIR_ERROR_* code the C call returned.
    WetHairResult code() const noexcept { return code_; }

private:
    WetHairResult code_;
};

namespace detail {
/// Throws Error when `r` is not WETHAIR_OK, with the per-thread message of the failed call.
inline void check(WetHairResult r) {
    if (r != WETHAIR_OK)
        throw Error(r, std::string(wethair_result_string(static_cast<uint32_t>(r))) + ": " + wethair_last_error_message());
}

/// An output struct with its struct_size set, as the C API asks.
template <class T> T sized() {
    T t{};
    t.struct_size = static_cast<uint32_t>(sizeof(T));
    return t;
}

/// Move-only ownership of a C object freed by `Destroy`.
template <class T, void (*Destroy)(T *)> class Handle {
public:
    Handle() noexcept = default;
    explicit Handle(T *p) noexcept : p_(p) {}
    Handle(const Handle &) = delete;
    Handle &operator=(const Handle &) = delete;
    Handle(Handle &&o) noexcept : p_(std::exchange(o.p_, nullptr)) {}
    Handle &operator=(Handle &&o) noexcept {
        if (this != &o) {
            reset();
            p_ = std::exchange(o.p_, nullptr);
        }
        return *this;
    }
    ~Handle() { reset(); }
    /// The C handle, still owned here.
    T *get() const noexcept { return p_; }
    explicit operator bool() const noexcept { return p_ != nullptr; }
    /// Frees the object now.
    void reset() noexcept {
        if (p_) Destroy(std::exchange(p_, nullptr));
    }

private:
    T *p_ = nullptr;
};
} // namespace detail

/// The library version as "major.minor.patch".
inline const char *version() noexcept { return wethair_version_string(); }

/// A simulation description with the paper scene's defaults (wethair_sim_desc_default).
inline WetHairSimDesc sim_desc() {
    WetHairSimDesc d;
    wethair_sim_desc_default(&d);
    return d;
}

/// A simulation description with the current defaults, right for any groom: springs from
/// material properties and the AUTO integrator (wethair_sim_desc_init).
inline WetHairSimDesc groom_sim_desc() {
    WetHairSimDesc d;
    detail::check(wethair_sim_desc_init(&d, sizeof d));
    return d;
}

/// Strands: rest positions, pinned roots, masses. Copied into each simulation made from it.
class Groom {
public:
    /// The paper's procedural scene: `strands` strands of `points` points on a 0.1 m head.
    static Groom paper_scene(uint32_t strands, uint32_t points) {
        WetHairGroom *g = nullptr;
        detail::check(wethair_groom_create_paper_scene(strands, points, &g));
        return Groom(g);
    }
    /// A .tfx or .hair file, `point_mass` kg per point.
    static Groom load(const std::string &path, float point_mass) {
        WetHairGroom *g = nullptr;
        detail::check(wethair_groom_load(path.c_str(), point_mass, &g));
        return Groom(g);
    }
    /// The host's own strands (see WetHairGroomDesc).
    static Groom create(const WetHairGroomDesc &desc) {
        WetHairGroom *g = nullptr;
        detail::check(wethair_groom_create(&desc, &g));
        return Groom(g);
    }
    /// Strand and point counts.
    std::pair<uint32_t, uint32_t> counts() const {
        uint32_t s = 0, p = 0;
        detail::check(wethair_groom_get_counts(h_.get(), &s, &p));
        return {s, p};
    }
    /// The C handle (owned here).
    const WetHairGroom *get() const noexcept { return h_.get(); }

private:
    explicit Groom(WetHairGroom *g) : h_(g) {}
    detail::Handle<WetHairGroom, wethair_groom_destroy> h_;
};

/// One wet-hair simulation. Calls on one simulation must not overlap.
class Simulation {
public:
    /// Creates a simulation from `desc` (desc.groom must be set; the groom is copied).
    explicit Simulation(const WetHairSimDesc &desc) {
        WetHairSim *s = nullptr;
        detail::check(wethair_sim_create(&desc, &s));
        h_ = Handle(s);
    }
    /// Creates a simulation on the host's own VkDevice (see wethair_sim_create_vulkan).
    static Simulation on_vulkan(const WetHairSimDesc &desc, const WetHairVulkanDevice &host) {
        WetHairSim *s = nullptr;
        detail::check(wethair_sim_create_vulkan(&desc, &host, &s));
        return Simulation(s);
    }

    /// Where the head is at the end of the next step: column-major 4x4 affine matrix.
    void set_head_transform(const std::array<float, 16> &m) { detail::check(wethair_sim_set_head_transform(h_.get(), m.data())); }
    /// Where SDF collider `index` is at the end of the next step: its grid frame to the world,
    /// column-major 4x4 (rotation, translation, uniform scale).
    void set_sdf_transform(uint32_t index, const std::array<float, 16> &m) {
        detail::check(wethair_sim_set_sdf_transform(h_.get(), index, m.data()));
    }
    /// Where collider `index`'s own frame is at the end of the next step (a simulation made
    /// with `collider_frames`): column-major 4x4 (rotation, translation, uniform scale).
    void set_collider_transform(uint32_t index, const std::array<float, 16> &m) {
        detail::check(wethair_sim_set_collider_transform(h_.get(), index, m.data()));
    }
    /// Where every strand's root is at the end of the next step (a simulation made with
    /// `skinned_roots`): x y z positions (m, world) and x y z w unit quaternions, one per strand.
    void set_root_frames(const std::vector<float> &positions, const std::vector<float> &rotations) {
        if (positions.size() % 3 != 0 || rotations.size() != positions.size() / 3 * 4)
            throw Error(WETHAIR_ERROR_INVALID_ARGUMENT, "set_root_frames: xyz positions and xyzw rotations, one each per strand");
        detail::check(wethair_sim_set_root_frames(h_.get(), positions.data(), rotations.data(),
                                                  static_cast<uint32_t>(positions.size() / 3)));
    }
    /// Simulates the first `fraction` of the guides from the next step on (a simulation made
    /// with `guides`): the output blends to the new guides over `guides.blend_time`.
    void set_guide_fraction(float fraction) { detail::check(wethair_sim_set_guide_fraction(h_.get(), fraction)); }
    /// Adds `count` particles; positions and velocities hold x y z each (velocities may be null).
    void add_water(const float *positions, const float *velocities, uint32_t count) {
        detail::check(wethair_sim_add_water(h_.get(), positions, velocities, count));
    }
    /// Adds particles from xyz-interleaved vectors (velocities empty: at rest).
    void add_water(const std::vector<float> &positions, const std::vector<float> &velocities = {}) {
        if (positions.size() % 3 != 0 || (!velocities.empty() && velocities.size() != positions.size()))
            throw Error(WETHAIR_ERROR_INVALID_ARGUMENT, "add_water: positions and velocities must be xyz triples of equal count");
        add_water(positions.data(), velocities.empty() ? nullptr : velocities.data(), static_cast<uint32_t>(positions.size() / 3));
    }
    /// Removes every particle.
    void clear_water() { detail::check(wethair_sim_clear_water(h_.get())); }
    /// Advances by `dt` seconds.
    void step(float dt) { detail::check(wethair_sim_step(h_.get(), dt)); }
    /// Advances by a host frame of `frame_time` seconds in the desc's fixed steps (the same
    /// steps at any frame rate); without a fixed step, one step of the frame.
    WetHairAdvance advance(float frame_time) {
        auto a = detail::sized<WetHairAdvance>();
        detail::check(wethair_sim_advance(h_.get(), frame_time, &a));
        return a;
    }
    /// Back to the rest pose, dry, at the current head transform.
    void reset() { detail::check(wethair_sim_reset(h_.get())); }

    /// Vertex count, stride and attribute offsets.
    WetHairVertexLayout layout() const {
        auto l = detail::sized<WetHairVertexLayout>();
        detail::check(wethair_sim_get_vertex_layout(h_.get(), &l));
        return l;
    }
    /// Copies the vertices into `dst` (resized to fit; no allocation once it is large enough).
    void vertices(std::vector<float> &dst) {
        auto l = layout();
        dst.resize(static_cast<size_t>(l.vertex_count) * l.stride_floats);
        size_t written = 0;
        detail::check(wethair_sim_get_vertex_buffer(h_.get(), dst.data(), dst.size(), &written));
    }
    /// The vertices in a new vector.
    std::vector<float> vertices() {
        std::vector<float> v;
        vertices(v);
        return v;
    }
    /// Particle positions, xyz interleaved.
    std::vector<float> water() const {
        std::vector<float> v(3 * static_cast<size_t>(counters().particles));
        uint32_t n = 0;
        detail::check(wethair_sim_get_water(h_.get(), v.data(), static_cast<uint32_t>(v.size() / 3), &n));
        v.resize(3 * static_cast<size_t>(n));
        return v;
    }
    /// Counters and measures (the measures are taken now: a search over the strands, and
    /// on the GPU a read back).
    WetHairStats stats() const {
        auto s = detail::sized<WetHairStats>();
        detail::check(wethair_sim_get_stats(h_.get(), &s));
        return s;
    }
    /// The counters alone (the measures -1): no search and no read of the positions, for
    /// every frame (on the GPU it waits for the last step).
    WetHairStats counters() const {
        auto s = detail::sized<WetHairStats>();
        detail::check(wethair_sim_get_counters(h_.get(), &s));
        return s;
    }
    /// Where the step runs and why.
    WetHairBackendInfo backend_info() const {
        auto b = detail::sized<WetHairBackendInfo>();
        detail::check(wethair_sim_get_backend_info(h_.get(), &b));
        return b;
    }
    /// The shared vertex VkBuffer and this frame's semaphore values (Vulkan-created only).
    WetHairVulkanBuffer vulkan_buffer() {
        auto b = detail::sized<WetHairVulkanBuffer>();
        detail::check(wethair_sim_get_vulkan_buffer(h_.get(), &b));
        return b;
    }
    /// The water's shared positions and indirect-draw VkBuffers, covered by the frame's
    /// semaphores (Vulkan-created only; the first call creates them).
    WetHairVulkanWater vulkan_water() {
        auto w = detail::sized<WetHairVulkanWater>();
        detail::check(wethair_sim_get_vulkan_water(h_.get(), &w));
        return w;
    }
    /// The C handle (owned here).
    WetHairSim *get() const noexcept { return h_.get(); }

private:
    using Handle = detail::Handle<WetHairSim, wethair_sim_destroy>;
    explicit Simulation(WetHairSim *s) : h_(s) {}
    Handle h_;
};

/// What a host's VkDevice must enable (see wethair_vulkan_requirements_create).
class VulkanRequirements {
public:
    explicit VulkanRequirements(const WetHairVulkanDevice &host) {
        WetHairVulkanRequirements *r = nullptr;
        detail::check(wethair_vulkan_requirements_create(&host, &r));
        h_ = Handle(r);
    }
    /// Extensions, the feature chain for VkDeviceCreateInfo::pNext, feature names.
    WetHairVulkanRequirementsInfo info() const {
        auto i = detail::sized<WetHairVulkanRequirementsInfo>();
        detail::check(wethair_vulkan_requirements_get_info(h_.get(), &i));
        return i;
    }

private:
    using Handle = detail::Handle<WetHairVulkanRequirements, wethair_vulkan_requirements_destroy>;
    Handle h_;
};

} // namespace wethair

#endif
