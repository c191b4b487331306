"""The Python module: loading, rendering to numpy, sample ranges and their merge, compare,
the GIL and Ctrl-C, and rendering on a local two-CPU Ray."""

import os
import pickle
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import glint
import glint.distributed

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CORNELL = os.path.join(ROOT, "scenes", "cornell-box.toml")


def small_scene(width=24):
    """A lit sphere on a plane, as a dict of the native format."""
    return {
        "camera": {"position": [0, 1, -5], "look_at": [0, 0.5, 0], "fov": 40, "resolution": [width, width]},
        "render": {"integrator": "path", "spp": 4, "max_depth": 4},
        "materials": {
            "white": {"type": "diffuse", "reflectance": [0.8, 0.8, 0.8]},
            "lamp": {"type": "diffuse", "reflectance": [0, 0, 0], "emission": [4, 4, 4]},
        },
        "shapes": [
            {"type": "sphere", "center": [0, 0.6, 0], "radius": 0.6, "material": "white"},
            {"type": "plane", "normal": [0, 1, 0], "material": "white"},
            {"type": "sphere", "center": [1.5, 3, -1], "radius": 0.5, "material": "lamp"},
        ],
    }


def test_load_dict_errors_say_what_is_wrong():
    with pytest.raises(glint.GlintError, match="missing field `look_at`"):
        glint.load_dict({"camera": {"position": [0, 0, -5], "resolution": [8, 8]}})
    broken = small_scene()
    broken["shapes"][0]["material"] = "whit"
    with pytest.raises(glint.GlintError, match="unknown material `whit`.*did you mean `white`"):
        glint.load_dict(broken)
    with pytest.raises(glint.GlintError, match="cannot"):
        glint.load_file(os.path.join(ROOT, "scenes", "no-such-scene.toml"))


def test_render_returns_float32_arrays_of_the_image_and_aovs():
    scene = glint.load_dict(small_scene(width=20))
    assert (scene.width, scene.height) == (20, 20)
    image = scene.render(spp=2, seed=1)
    assert image.shape == (20, 20, 3) and image.dtype == np.float32
    assert image.max() > 0.05
    assert np.array_equal(image, scene.render(spp=2, seed=1)), "same seed, same image"
    assert np.array_equal(image, scene.render(spp=2, seed=1, threads=1)), "any thread count"
    layers = scene.render(spp=2, aovs=True)
    assert layers["image"].shape == (20, 20, 3) and layers["albedo"].dtype == np.float32
    assert layers["normal"].shape == (20, 20, 3) and layers["depth"].shape == (20, 20)
    # The sphere's centre pixel: white albedo, facing the camera.
    assert abs(layers["albedo"][12, 10, 0] - 0.8) < 0.1
    with pytest.raises(ValueError, match="unknown integrator"):
        scene.render(integrator="paht")


def test_merges_of_two_three_and_seven_ranges_equal_one_render_bit_for_bit():
    scene = glint.load_dict(small_scene())
    whole = scene.render(samples=(0, 14), seed=3)
    for splits in ([0, 9, 14], [0, 1, 6, 14], [0, 2, 4, 6, 8, 10, 12, 14]):
        parts = [scene.render(samples=(a, b), seed=3) for a, b in zip(splits, splits[1:])]
        merged = glint.merge(list(reversed(parts)))
        assert merged.samples == [(0, 14)]
        assert np.array_equal(merged.image, whole.image), splits
    # Parts pickle (as Ray sends them) and still merge.
    a, b = scene.render(samples=(0, 5), seed=3), scene.render(samples=(5, 14), seed=3)
    assert np.array_equal(glint.merge([pickle.loads(pickle.dumps(a)), b]).image, whole.image)
    with pytest.raises(glint.GlintError, match="both hold samples 3..5"):
        glint.merge([a, scene.render(samples=(3, 7), seed=3)])
    with pytest.raises(glint.GlintError, match="seed"):
        glint.merge([a, scene.render(samples=(5, 9), seed=4)])
    with pytest.raises(ValueError, match="empty"):
        scene.render(samples=(4, 4))
    with pytest.raises(ValueError, match="spp or samples"):
        scene.render(spp=4, samples=(0, 4))


def test_compare_metrics_on_hand_made_images():
    image = np.array([[[1, 2, 0], [3, 2, 0.1]]], dtype=np.float32)
    reference = np.array([[[1, 1, 0], [1, 1, 0]]], dtype=np.float32)
    result = glint.compare(image, reference)
    assert result["mse"] == pytest.approx([2.0, 1.0, 0.005])
    assert result["mae"] == pytest.approx([1.0, 1.0, 0.05])
    assert result["rel_mse"][0] == pytest.approx(2.0 / 1.01)
    assert result["mean_ratio"][:2] == pytest.approx([2.0, 2.0])
    assert result["flip"] > 0 and result["z_test"] is None
    same = glint.compare(reference, reference, variance=np.ones_like(reference), spp=100)
    assert same["mse"] == [0, 0, 0] and same["flip"] == 0 and same["z_test"]["passed"]
    with pytest.raises(ValueError, match="shape"):
        glint.compare(np.zeros((2, 2)), reference)
    with pytest.raises(ValueError, match="expected a path or a numpy array"):
        glint.compare([[1, 2, 3]], reference)


def test_the_gil_is_released_while_rendering():
    scene = glint.load_file(CORNELL)
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    counter = threading.Thread(target=count)
    counter.start()
    start = time.perf_counter()
    scene.render(spp=24)
    elapsed = time.perf_counter() - start
    done.set()
    counter.join()
    during = [t for t in ticks if start <= t <= start + elapsed]
    # A thread sleeping 5 ms a tick gets about elapsed / 5 ms ticks if the GIL is free.
    assert elapsed > 0.2 and len(during) > 0.5 * elapsed / 0.005, (elapsed, len(during))


def test_ctrl_c_stops_a_render_with_keyboard_interrupt():
    script = f"""
import os, signal, threading, time, glint
scene = glint.load_file({CORNELL!r})
threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
start = time.time()
try:
    scene.render(spp=100000)
    print("finished")
except KeyboardInterrupt:
    print("interrupted after", round(time.time() - start, 2))
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert "interrupted after" in out.stdout, out.stdout + out.stderr
    assert float(out.stdout.split()[-1]) < 5.0, out.stdout


def test_ranges_split_evenly():
    assert glint.distributed.ranges(10, 4) == [(0, 2), (2, 5), (5, 7), (7, 10)]
    assert glint.distributed.ranges(3, 8) == [(0, 1), (1, 2), (2, 3)]
    with pytest.raises(ValueError):
        glint.distributed.ranges(0, 2)


def test_ray_renders_the_cornell_box_in_four_tasks_as_one_process_does():
    import ray
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        merged = glint.distributed.render(CORNELL, spp=8, tasks=4, seed=2)
    finally:
        ray.shutdown()
    single = glint.load_file(CORNELL).render(samples=(0, 8), seed=2)
    assert merged.samples == [(0, 8)]
    assert np.array_equal(merged.image, single.image)


def test_ray_joins_an_existing_cluster_by_its_address():
    """A Ray head started apart (as a cluster's would be), joined by `address`, the driver a
    separate process: the same image as one process renders."""
    ray_cli = os.path.join(os.path.dirname(sys.executable), "ray")
    port = 6000 + os.getpid() % 2000
    # A local test cluster without Ray's token authentication (a real cluster's driver is
    # given its token as Ray's documentation says).
    env = dict(os.environ, RAY_USAGE_STATS_ENABLED="0", RAY_AUTH_MODE="disabled")
    subprocess.run([ray_cli, "start", "--head", f"--port={port}", "--num-cpus=2", "--include-dashboard=false"],
                   check=True, capture_output=True, env=env, timeout=120)
    try:
        script = f"""
import glint.distributed, numpy as np
merged = glint.distributed.render({CORNELL!r}, spp=4, tasks=2, seed=5, address="127.0.0.1:{port}")
single = glint.load_file({CORNELL!r}).render(samples=(0, 4), seed=5)
print("equal" if np.array_equal(merged.image, single.image) else "different", merged.samples)
"""
        out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, timeout=300)
        assert "equal [(0, 4)]" in out.stdout, out.stdout + out.stderr
    finally:
        subprocess.run([ray_cli, "stop", "--force"], capture_output=True, env=env, timeout=120)
