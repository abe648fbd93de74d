"""The GIL is released while C++ renders: two renders in two Python threads run at the same
time (seen from a third thread while both are inside C++), with the single-render images;
Ctrl-C (SIGINT) stops a long render between tiles and is raised by render()."""

from __future__ import annotations

import os
import signal
import threading
import time

import numpy

import softpbr


def slow_scene(width=192, height=192, lights=128):
    """A sphere filling the frame under many lights: every light is evaluated at every pixel."""
    return {"camera": {"position": [0, 0, 2.2], "target": [0, 0, 0], "fov": 45},
            "lights": [{"type": "point", "position": [3 * ((i % 7) - 3) / 3, 2 + (i % 5) * 0.1, 3], "intensity": 0.5}
                       for i in range(lights)],
            "objects": [{"mesh": {"type": "uv_sphere", "radius": 1, "segments": 48, "rings": 24},
                         "material": {"preset": "gold", "roughness": 0.4}}],
            "render": {"width": width, "height": height, "threads": 1, "tile_size": 16}}


def test_two_threads_render_at_the_same_time():
    scene = softpbr.Scene.from_dict(slow_scene())
    start = time.perf_counter()
    expected = softpbr.render(scene)
    one = time.perf_counter() - start

    results = [None, None]
    barrier = threading.Barrier(3)

    def work(i):
        barrier.wait()
        results[i] = softpbr.render(scene)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    barrier.wait()
    start = time.perf_counter()
    most = 0
    # This thread runs Python only because both renders released the GIL.
    while any(t.is_alive() for t in threads):
        most = max(most, softpbr.active_renders())
        time.sleep(0.001)
    two = time.perf_counter() - start
    for t in threads:
        t.join()
    assert most == 2, "the two renders were never inside C++ at the same time"
    for r in results:
        assert numpy.array_equal(r, expected)
    # Measured, not asserted (the machine may be busy): two renders of one thread each.
    print(f"one render {one * 1000:.0f} ms; two in two threads {two * 1000:.0f} ms ({two / one:.2f}x one)")


class Interrupted(Exception):
    pass


def raise_interrupted(signum, frame):
    raise Interrupted()


def test_ctrl_c_stops_a_long_render_and_is_raised_by_it():
    # ~5 s in full on one Zen 5 core with AVX-512 (1024 x 1024 with 256 lights took 0.3 s, as
    # long as the timer): the render must still be running when SIGINT arrives.
    scene = softpbr.Scene.from_dict(slow_scene(width=4096, height=4096, lights=256))
    previous = signal.signal(signal.SIGINT, raise_interrupted)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    try:
        start = time.perf_counter()
        timer.start()
        try:
            softpbr.render(scene)
            raise AssertionError("the render finished: SIGINT did not stop it")
        except Interrupted as e:
            notes = getattr(e, "__notes__", [])
            assert any("stopped early" in n for n in notes), notes
        took = time.perf_counter() - start
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    print(f"interrupted after {took * 1000:.0f} ms")
    # The module renders normally afterwards.
    small = softpbr.Scene.from_dict(slow_scene(width=32, height=32, lights=2))
    assert numpy.array_equal(softpbr.render(small), softpbr.render(small, threads=2))


def test_a_scene_changed_while_it_renders_does_not_change_that_render():
    scene = softpbr.Scene.from_dict(slow_scene())
    expected = softpbr.render(scene)
    result = []
    worker = threading.Thread(target=lambda: result.append(softpbr.render(scene)))
    worker.start()
    while softpbr.active_renders() == 0 and worker.is_alive():
        time.sleep(0.0005)
    # The render took its copy of the scene before entering C++.
    for _ in range(50):
        scene.add(softpbr.Mesh.cube(0.2), softpbr.Material.preset("gold"))
        scene.lights = []
    worker.join()
    assert numpy.array_equal(result[0], expected)
    assert not numpy.array_equal(softpbr.render(scene), expected)
