"""The Python module: loading, rendering to numpy, sample ranges and their merge, compare,
the GIL and Ctrl-C, and rendering on a local two-CPU Ray."""

import copy
import json
import multiprocessing
import os
import pathlib
import pickle
import re
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


def run_glint_cli(args, env=None):
    """Runs the `glint` command (built beside the wheel by tests/python.rs)."""
    cli = os.environ.get("GLINT_CLI") or os.path.join(ROOT, "target", "release", "glint")
    if not os.path.exists(cli):
        pytest.skip("the glint command is not built (tests/python.rs builds it and sets GLINT_CLI)")
    return subprocess.run([cli, *args], capture_output=True, text=True, env=env, timeout=120)


def glint_cli(*args, env=None):
    """Runs the `glint` command, which must refuse; its stderr."""
    out = run_glint_cli(args, env=env)
    assert out.returncode != 0, out.stderr
    return out.stderr


def glint_cli_ok(*args):
    """Runs the `glint` command, which must succeed; its stderr."""
    out = run_glint_cli(args)
    assert out.returncode == 0, out.stderr
    return out.stderr


def test_load_dict_errors_say_what_is_wrong():
    with pytest.raises(glint.GlintError, match="^camera: missing field `look_at`"):
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
    with pytest.raises(ValueError, match="^samples: the range 4..4 is empty"):
        scene.render(samples=(4, 4))
    # The command's checks, in Python's names.
    with pytest.raises(ValueError, match="^samples renders exactly the samples it names: it cannot be combined with spp$"):
        scene.render(spp=4, samples=(0, 4))
    with pytest.raises(ValueError, match="leave aovs to the merged render"):
        scene.render(samples=(0, 4), aovs=True)
    with pytest.raises(ValueError, match="^samples: `light` does not take samples of its own per pixel"):
        scene.render(samples=(0, 4), integrator="light")


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


def test_compare_leaves_out_non_finite_pixels_with_a_warning():
    # A +inf in the reference raised a PanicException (HDR-FLIP's exposure range was infinite).
    reference = np.full((8, 8, 3), 0.5, dtype=np.float32)
    reference[0, 3] = np.inf
    reference[2, 1, 0] = np.nan
    image = reference + np.float32(0.5)
    with pytest.warns(glint.GlintWarning, match="2 pixels with a NaN or infinite value"):
        result = glint.compare(image, reference)
    assert result["non_finite_pixels"] == {"image": 2, "reference": 2, "left_out": 2}
    assert result["mae"] == pytest.approx([0.5, 0.5, 0.5])
    assert result["flip"] > 0.05


def test_a_black_render_says_why():
    unlit = small_scene(width=8)
    unlit["shapes"] = unlit["shapes"][:2]  # the lamp gone
    del unlit["materials"]["lamp"]
    with pytest.warns(glint.GlintWarning, match="black in every pixel: the scene has no light"):
        image = glint.load_dict(unlit).render(spp=1)
    assert not image.any()


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


def test_the_memory_limit_holds_in_python_as_on_the_command_line(tmp_path, monkeypatch):
    """GLINT_MEMORY_LIMIT (GiB) is read as the command reads it, and a render whose buffers
    exceed it is refused with the command's own words."""
    description = small_scene(width=256)
    scene_file = tmp_path / "scene.json"
    scene_file.write_text(json.dumps(description))
    monkeypatch.setenv("GLINT_MEMORY_LIMIT", "0.001")
    scene = glint.load_dict(description)
    with pytest.raises(glint.GlintError, match="memory limit of 1 MiB") as refused:
        scene.render(spp=1)
    message = str(refused.value)
    assert message.startswith("this render needs about 2 MiB (256x256 pixels)"), message
    stderr = glint_cli("render", str(scene_file), "--spp", "1", "-o", str(tmp_path / "x.pfm"), env=dict(os.environ))
    assert f"error: {message}" in stderr.splitlines(), stderr
    # The scene readers hold what they read to it too.
    monkeypatch.setenv("GLINT_MEMORY_LIMIT", "0.00001")
    with pytest.raises(glint.GlintError, match="more than the memory limit"):
        glint.load_file(CORNELL)
    monkeypatch.setenv("GLINT_MEMORY_LIMIT", "lots")
    with pytest.raises(glint.GlintError, match="GLINT_MEMORY_LIMIT must be a number of GiB, got `lots`"):
        scene.render(spp=1)


def test_thread_counts_are_bounded_as_on_the_command_line():
    scene = glint.load_dict(small_scene(width=16))
    for threads in (0, -1, 1025):
        with pytest.raises(ValueError, match=f"worker threads must be from 1 to 1024, got {threads}$"):
            scene.render(spp=1, threads=threads)
    # A hundred thousand threads ran until the machine gave out: in a process of its own.
    script = f"""
import glint
scene = glint.load_dict({small_scene(width=16)!r})
try:
    scene.render(spp=1, threads=100000)
    print("rendered")
except ValueError as e:
    print(e)
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    message = out.stdout.strip()
    assert message == "the number of worker threads must be from 1 to 1024, got 100000", out.stdout + out.stderr
    assert message in glint_cli("render", "--spp", "1", "--threads", "100000", "-o", "never.pfm")


def test_a_part_is_saved_in_the_format_its_extension_names(tmp_path):
    part = glint.load_dict(small_scene(width=8)).render(samples=(0, 2), seed=1)
    part.save(str(tmp_path / "part.png"))
    assert (tmp_path / "part.png").read_bytes()[:4] == b"\x89PNG"
    part.save(tmp_path / "part.pfm")
    assert (tmp_path / "part.pfm").read_bytes()[:2] == b"PF"
    part.save(tmp_path / "part.exr")
    assert (tmp_path / "part.exr").read_bytes()[:4] == b"\x76\x2f\x31\x01"
    with pytest.raises(glint.GlintError, match=r"must end in \.png, \.exr, \.hdr or \.pfm"):
        part.save(tmp_path / "part.jpg")
    assert not (tmp_path / "part.jpg").exists()


def test_the_distributed_command_writes_the_format_its_output_names(tmp_path, monkeypatch):
    scene = glint.load_dict(small_scene(width=8))
    calls = []

    def render(scene_path, spp, **options):
        calls.append(scene_path)
        return scene.render(samples=(0, spp), seed=1)

    monkeypatch.setattr(glint.distributed, "render", render)
    glint.distributed.main([CORNELL, "--spp", "2", "-o", str(tmp_path / "dist.png")])
    assert (tmp_path / "dist.png").read_bytes()[:4] == b"\x89PNG"
    # An output it cannot write is refused before any rendering.
    with pytest.raises(glint.GlintError, match="must end in"):
        glint.distributed.main([CORNELL, "--spp", "2", "-o", str(tmp_path / "dist.jpg")])
    assert len(calls) == 1


def test_render_arguments_out_of_range_say_which_and_why():
    scene = glint.load_dict(small_scene(width=8))
    for spp in (-1, 0, 2**32):
        with pytest.raises(ValueError, match=f"^spp must be a whole number from 1 to 4294967295, got {spp}$"):
            scene.render(spp=spp)
    with pytest.raises(ValueError, match="^seed must be a whole number from 0 to 18446744073709551615, got -1$"):
        scene.render(spp=1, seed=-1)
    with pytest.raises(TypeError, match="^spp must be a whole number, got 2.5"):
        scene.render(spp=2.5)
    assert np.array_equal(scene.render(spp=np.int64(2), seed=np.uint64(4)), scene.render(spp=2, seed=4))
    whole = scene.render(samples=(0, 2), seed=1).image
    assert np.array_equal(scene.render(samples=[0, 2], seed=1).image, whole)
    assert np.array_equal(scene.render(samples=np.array([0, 2]), seed=1).image, whole)
    with pytest.raises(ValueError, match=r"^samples must be a pair \(a, b\) of sample indices, got \[0, 1, 2\]"):
        scene.render(samples=[0, 1, 2])
    with pytest.raises(ValueError, match="^samples: a must be a whole number from 0 to 4294967295, got -1"):
        scene.render(samples=(-1, 2))


def test_load_file_takes_str_bytes_and_path_like_paths():
    image = glint.load_file(CORNELL).render(spp=1, seed=1)
    assert np.array_equal(glint.load_file(os.fsencode(CORNELL)).render(spp=1, seed=1), image)
    assert np.array_equal(glint.load_file(pathlib.Path(CORNELL)).render(spp=1, seed=1), image)
    with pytest.raises(TypeError, match="expected str, bytes or os.PathLike"):
        glint.load_file(3)


def test_load_dict_takes_numpy_values_and_names_key_paths_in_errors():
    plain = small_scene(width=12)
    typed = small_scene(width=12)
    typed["camera"]["resolution"] = np.array([12, 12])
    typed["camera"]["fov"] = np.float64(40)
    typed["shapes"][0]["center"] = np.array([0, 0.6, 0])
    typed["shapes"][0]["radius"] = np.float64(0.6)
    typed["render"]["spp"] = np.int32(4)
    typed["materials"]["white"]["reflectance"] = [np.float32(0.8)] * 3
    rendered = glint.load_dict(typed).render(spp=1, seed=1)
    assert rendered.shape == (12, 12, 3)
    plain["materials"]["white"]["reflectance"] = [float(np.float32(0.8))] * 3
    assert np.array_equal(rendered, glint.load_dict(plain).render(spp=1, seed=1))
    wrong = small_scene()
    wrong["shapes"][0]["radius"] = "big"
    with pytest.raises(glint.GlintError, match=r'^shapes\[0\]\.radius: invalid type: string "big", expected'):
        glint.load_dict(wrong)
    typo = small_scene()
    typo["shapes"][1]["nromal"] = typo["shapes"][1].pop("normal")
    with pytest.raises(glint.GlintError, match=r"^shapes\[1\]\.nromal: unknown field `nromal`.*did you mean `normal`"):
        glint.load_dict(typo)
    unknown = small_scene()
    unknown["shapes"][2]["material"] = "lmap"
    with pytest.raises(glint.GlintError, match=r"^shapes\[2\]\.material: .*unknown material `lmap`.*did you mean `lamp`") as e:
        glint.load_dict(unknown)
    assert "<dict>" not in str(e.value)
    not_finite = small_scene()
    not_finite["shapes"][0]["radius"] = float("nan")
    with pytest.raises(glint.GlintError, match=r"^shapes\[0\]\.radius: NaN is not a number a scene description can hold"):
        glint.load_dict(not_finite)
    odd = small_scene()
    odd["shapes"][0]["radius"] = object()
    with pytest.raises(glint.GlintError, match=r"^shapes\[0\]\.radius: a value of type `object`, which a scene description cannot hold"):
        glint.load_dict(odd)
    looped = small_scene()
    looped["render"]["loop"] = looped
    with pytest.raises(glint.GlintError, match="levels deep"):
        glint.load_dict(looped)


def test_errors_pickle_so_a_worker_process_reports_them():
    with pytest.raises(glint.GlintError) as e:
        glint.load_file(os.path.join(ROOT, "scenes", "no-such-scene.toml"))
    copied = pickle.loads(pickle.dumps(e.value))
    assert type(copied) is glint.GlintError and str(copied) == str(e.value)
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        with pytest.raises(glint.GlintError, match="no-such-scene.toml"):
            pool.apply(glint.load_file, (os.path.join(ROOT, "scenes", "no-such-scene.toml"),))


def test_scenes_pickle_and_copy(tmp_path):
    for scene in (glint.load_dict(small_scene(width=10)), glint.load_file(CORNELL)):
        image = scene.render(spp=1, seed=2)
        for other in (pickle.loads(pickle.dumps(scene)), copy.copy(scene), copy.deepcopy(scene)):
            assert (other.width, other.height, other.settings) == (scene.width, scene.height, scene.settings)
            assert np.array_equal(other.render(spp=1, seed=2), image)
        # Parts of a scene and of its unpickled copy are parts of one render.
        merged = glint.merge([scene.render(samples=(0, 1)), pickle.loads(pickle.dumps(scene)).render(samples=(1, 2))])
        assert merged.samples == [(0, 2)]
    # A scene pickles as where it came from: one whose file changed since is refused.
    scene_file = tmp_path / "scene.json"
    scene_file.write_text(json.dumps(small_scene(width=10)))
    pickled = pickle.dumps(glint.load_file(scene_file))
    scene_file.write_text(json.dumps(small_scene(width=12)))
    with pytest.raises(glint.GlintError, match="changed since it was pickled"):
        pickle.loads(pickled)


def test_load_warnings_reach_python_as_warnings():
    bright = small_scene(width=8)
    bright["materials"]["white"]["reflectance"] = [1.5, 1.5, 1.5]
    with pytest.warns(glint.GlintWarning, match="material `white` reflects or transmits more light than it receives"):
        glint.load_dict(bright)


# A Mitsuba scene with a parameter (the sphere's radius): the parameters are part of a
# render's identity, from the command's -D as from load_file's keywords.
MITSUBA_SPHERE = """<scene version="3.0.0">
    <default name="radius" value="0.5"/>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 0, -4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm"><integer name="width" value="20"/><integer name="height" value="16"/></film>
    </sensor>
    <integrator type="path"><integer name="max_depth" value="4"/></integrator>
    <shape type="sphere"><float name="radius" value="$radius"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.5, 0.3"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="1" y="2" z="-1"/><float name="radius" value="0.3"/>
        <emitter type="area"><rgb name="radiance" value="8, 8, 8"/></emitter></shape>
    <emitter type="constant"><rgb name="radiance" value="0.1, 0.1, 0.2"/></emitter>
</scene>
"""


def test_parts_from_python_and_the_command_merge_bit_for_bit(tmp_path):
    """One render's samples split between the two front ends: the merge equals the command's
    render of both halves (and of all the samples) bit for bit, in either order, through
    either front end's merge; a part of another render is still refused."""
    native = tmp_path / "scene.json"
    native.write_text(json.dumps(small_scene(width=24)))
    mitsuba = tmp_path / "sphere.xml"
    mitsuba.write_text(MITSUBA_SPHERE)
    for scene_file, params in ((native, {}), (mitsuba, {"radius": 0.75})):
        defines = [arg for name, value in params.items() for arg in ("-D", f"{name}={value}")]

        def cli_part(a, b, seed=3):
            out = tmp_path / f"cli-{scene_file.stem}-{a}-{b}-{seed}.exr"
            glint_cli_ok("render", str(scene_file), *defines, "--samples", f"{a}..{b}", "--seed", str(seed),
                         "-q", "-o", str(out))
            return out

        # The command's own: both halves merged by `glint merge`, and all the samples at once.
        cli_first, cli_second = cli_part(0, 3), cli_part(3, 8)
        both = tmp_path / f"both-{scene_file.stem}.exr"
        glint_cli_ok("merge", "-q", str(both), str(cli_first), str(cli_second))
        whole = glint.load_partial(both)
        assert whole.samples == [(0, 8)]
        assert np.array_equal(whole.image, glint.load_partial(cli_part(0, 8)).image)
        assert whole.image.max() > 0.01

        scene = glint.load_file(scene_file, **params)
        py_first, py_second = scene.render(samples=(0, 3), seed=3), scene.render(samples=(3, 8), seed=3)
        for parts in ([py_first, glint.load_partial(cli_second)], [glint.load_partial(cli_first), py_second]):
            merged = glint.merge(parts)
            assert merged.samples == [(0, 8)]
            assert np.array_equal(merged.image, whole.image), scene_file
        # The command merges a part Python saved with one of its own.
        py_first.save(tmp_path / "py-first.exr")
        mixed = tmp_path / f"mixed-{scene_file.stem}.exr"
        glint_cli_ok("merge", "-q", str(mixed), str(tmp_path / "py-first.exr"), str(cli_second))
        assert np.array_equal(glint.load_partial(mixed).image, whole.image)

        # Parts of other renders: another seed, another parameter.
        with pytest.raises(glint.GlintError, match="`glint:seed` differ"):
            glint.merge([py_first, glint.load_partial(cli_part(3, 8, seed=4))])
    other = glint.load_file(mitsuba, radius=0.5).render(samples=(0, 3), seed=3)
    with pytest.raises(glint.GlintError, match="`glint:identity` differ"):
        glint.merge([other, py_second])


def test_the_job_warns_in_python_as_on_the_command_line(tmp_path):
    """The scene's `moment` that a render cannot keep: the command's warning, as a
    GlintWarning; a camera render keeps it and returns it with the AOVs, beside the
    variance."""
    description = small_scene(width=12)
    description["render"]["moment"] = True
    scene = glint.load_dict(description)
    message = "the scene asks for the second moment (`moment`), which is not written: `light` splats particles"
    with pytest.warns(glint.GlintWarning, match=re.escape(message)):
        scene.render(spp=1, integrator="light")
    scene_file = tmp_path / "moment.json"
    scene_file.write_text(json.dumps(description))
    stderr = glint_cli_ok("render", str(scene_file), "--spp", "1", "--integrator", "light", "-q",
                          "-o", str(tmp_path / "m.pfm"))
    assert f"warning: {message}" in stderr, stderr
    layers = scene.render(spp=4, seed=1, aovs=True)
    assert layers["m2"].shape == (12, 12, 3) and layers["variance"].shape == (12, 12, 3)
    assert (layers["m2"] >= layers["image"] ** 2 * 0.999).all()
    assert np.allclose(layers["variance"], np.maximum(layers["m2"] - layers["image"] ** 2, 0) / 4, rtol=1e-5, atol=1e-7)


def test_the_memory_limit_counts_the_photon_maps_in_python_as_on_the_command_line(tmp_path, monkeypatch):
    description = small_scene(width=8)
    description["render"]["photons"] = 200_000_000
    scene_file = tmp_path / "photons.json"
    scene_file.write_text(json.dumps(description))
    scene = glint.load_file(scene_file)
    with pytest.raises(glint.GlintError, match="pixels and the photon maps") as refused:
        scene.render(spp=1, integrator="photon")
    stderr = glint_cli("render", str(scene_file), "--integrator", "photon", "-o", str(tmp_path / "x.pfm"))
    assert f"error: {refused.value}" in stderr.splitlines(), stderr
