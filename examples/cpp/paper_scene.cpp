// The paper scene through the C++ wrapper (bindings/cpp/wethair.hpp): dry, then showered with
// 1,000 particles; checks that water clumps the hair and that a bad call throws
// wethair::Error with its code and leaves the output untouched. Exit 0 on success.
#include <cmath>
#include <cstdio>
#include <vector>

#include "wethair.hpp"

int main() {
    try {
        auto groom = wethair::Groom::paper_scene(10000, 6);
        auto [strands, points] = groom.counts();
        WetHairSimDesc desc = wethair::sim_desc();
        WetHairCollider head = {WETHAIR_COLLIDER_SPHERE, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.1f};
        desc.groom = groom.get();
        desc.colliders = &head;
        desc.collider_count = 1;
        desc.backend = WETHAIR_BACKEND_CPU;
        wethair::Simulation dry(desc), wet(desc);

        // A shower like the C hosts': a 0.16 m disc 0.3 m above the head, falling at 1 m/s.
        uint32_t state = 12345;
        auto rnd = [&state] {
            state = state * 1664525u + 1013904223u;
            return static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
        };
        std::vector<float> pos, vel, verts;
        for (int f = 0; f < 60; f++) {
            if (f < 20) {
                pos.clear();
                vel.clear();
                for (int i = 0; i < 50; i++) {
                    float r = 0.16f * std::sqrt(rnd()), th = 6.2831853f * rnd();
                    pos.insert(pos.end(), {r * std::cos(th), r * std::sin(th), 0.3f});
                    vel.insert(vel.end(), {0.0f, 0.0f, -1.0f});
                }
                wet.add_water(pos, vel);
            }
            dry.step(1.0f / 60.0f);
            wet.step(1.0f / 60.0f);
        }
        wet.vertices(verts);
        for (float v : verts)
            if (!std::isfinite(v)) {
                std::fprintf(stderr, "non-finite vertex\n");
                return 1;
            }
        WetHairStats sd = dry.stats(), sw = wet.stats(), cw = wet.counters();
        if (cw.particles != sw.particles || cw.steps != sw.steps || cw.clumping != -1.0f) {
            std::fprintf(stderr, "counters differ from the stats' counters\n");
            return 1;
        }
        std::printf("C++ wrapper (wethair %s): %u strands x %u points; clumping dry %.5f m, wet %.5f m (ratio %.3f), %u particles held\n",
                    wethair::version(), strands, points / strands, sd.clumping, sw.clumping, sw.clumping / sd.clumping,
                    sw.particles);
        if (!(sw.clumping < 0.9f * sd.clumping)) {
            std::fprintf(stderr, "water did not clump the hair\n");
            return 1;
        }

        // The error path: a NaN step throws with its code; the simulation still works after.
        try {
            wet.step(std::nanf(""));
            std::fprintf(stderr, "a NaN dt did not throw\n");
            return 1;
        } catch (const wethair::Error &e) {
            if (e.code() != WETHAIR_ERROR_INVALID_ARGUMENT) {
                std::fprintf(stderr, "wrong code %d: %s\n", static_cast<int>(e.code()), e.what());
                return 1;
            }
            std::printf("threw as documented: %s\n", e.what());
        }
        wet.step(1.0f / 60.0f);
        // Moving a simulation keeps one owner; the moved-from handle is empty and harmless.
        wethair::Simulation moved = std::move(wet);
        moved.step(1.0f / 60.0f);
        // Without a fixed step in the desc, advance is one step of the frame.
        if (moved.advance(1.0f / 60.0f).steps != 1) {
            std::fprintf(stderr, "advance without a fixed step did not take one step\n");
            return 1;
        }
        return 0;
    } catch (const wethair::Error &e) {
        std::fprintf(stderr, "wethair error %d: %s\n", static_cast<int>(e.code()), e.what());
        return 1;
    }
}
