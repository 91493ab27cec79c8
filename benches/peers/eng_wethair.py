"""wethair through its Python package (bindings/python: ctypes over the C ABI, NumPy out):
the paper scene's exact parameters (preset "paper"), the CPU backend with `threads`
workers, positions only."""

import wethair

import scene as sc


class Engine:
    name, variant = "wethair", "CPU backend"

    def __init__(self, strands, points, threads):
        self.version = wethair.version()
        self.threads = threads
        self.backend = f"cpu, {threads} thread{'s' if threads > 1 else ''}"
        with wethair.Groom.paper_scene(strands, points) as groom:
            self.sim = wethair.Simulation(
                groom, preset="paper", backend="cpu", threads=threads, vertex_attributes=["position"]
            )

    def step_frame(self):
        self.sim.step(sc.FRAME_DT)

    def positions(self):
        return self.sim.strands().copy()
