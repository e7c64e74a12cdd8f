"""`import candela` (python/): frames equal `candela render` bit for bit, every setting of the schema is a
keyword argument, bad input raises with the command line's message, arrays have the documented layout, and
a long loop of frames does not grow memory."""
import subprocess

import numpy as np
import pytest

import candela

SMALL = dict(width=32, height=24)


def render_cli(binary, tmp_path, scene, args):
    out = tmp_path / "frame.exr"
    subprocess.run([binary, "render", scene, "--out", str(out), "-q", *args], check=True)
    return candela.read_image(str(out))


@pytest.mark.parametrize("method", ["pt", "direct", "restir-di", "restir"])
def test_frames_equal_candela_render(binary, tmp_path, manylights, method):
    expected = render_cli(binary, tmp_path, "builtin:manylights",
                          ["--lights", "64", "--width", "32", "--height", "24", "--spp", "2", "--frames", "3",
                           "--method", method, "--denoise", "svgf"])
    r = candela.Renderer(manylights, method=method, spp=2, denoise="svgf", **SMALL)
    for _ in range(3):
        frame = r.render_frame()
    assert np.array_equal(frame.radiance, expected)
    assert frame.index == 2 and r.frames_rendered == 3


def non_default(row):
    """A value of the row other than its default, of the row's Python type."""
    if row["type"] == "str":
        return next(n for n in row["names"] if n != row["default"])
    if row["type"] == "bool":
        return not row["default"]
    if "values" in row:
        return next(v for v in row["values"] if v != row["default"])
    value = row["max"] if row["default"] != row["max"] else row["min"]
    return int(value) if row["type"] == "int" else float(value)


def test_every_schema_setting_is_a_keyword(cornell):
    rows = candela.settings_schema()
    assert {"method", "di_neighbours", "gi_max_age", "denoise", "svgf_kernel"} <= {row["key"] for row in rows}
    defaults = candela.Renderer(cornell).settings
    for row in rows:
        value = non_default(row)
        if row["key"] in ("width", "height"):
            value = 24
        elif row["key"] == "spp":
            value = 2
        r = candela.Renderer(cornell, **{row["key"]: value})
        assert r.settings[row["key"]] == value, row["key"]
        changed = [k for k in defaults if r.settings[k] != defaults[k]]
        assert changed == [row["key"]], row["key"]


def test_bad_input_raises_with_the_message(cornell):
    with pytest.raises(TypeError, match="unknown setting 'di_neighbors'.*known: .*di_neighbours"):
        candela.Renderer(cornell, di_neighbors=3)
    with pytest.raises(ValueError, match="di_neighbours: must be in 0..31, got 40"):
        candela.Renderer(cornell, di_neighbours=40)
    with pytest.raises(ValueError, match="method: must be one of .*restir-di.*, got 'magic'"):
        candela.Renderer(cornell, method="magic")
    with pytest.raises(ValueError, match="svgf_kernel: must be 3 or 5, got 4"):
        candela.Renderer(cornell, svgf_kernel=4)
    with pytest.raises(TypeError, match="jitter: expected a bool"):
        candela.Renderer(cornell, jitter=1)
    with pytest.raises(TypeError, match="spp: expected an int"):
        candela.Renderer(cornell, spp=2.5)
    with pytest.raises(ValueError, match="seed: must be in 0..9007199254740991, got"):
        candela.Renderer(cornell, seed=2**70)
    assert candela.Renderer(cornell, spp=np.int64(3), **SMALL).settings["spp"] == 3  # NumPy integers are ints
    with pytest.raises(ValueError, match="width x height"):
        candela.Renderer(cornell, width=16384, height=16384)
    with pytest.raises(candela.InputError, match="unknown built-in scene 'builtin:nope'"):
        candela.load_scene("builtin:nope")
    with pytest.raises(candela.InputError, match="no_such.gltf"):
        candela.load_scene("no_such.gltf")
    with pytest.raises(ValueError, match="target: equals the position"):
        candela.Camera((0, 1, 2), (0, 1, 2))
    frame = candela.Renderer(cornell, **SMALL).render_frame()
    with pytest.raises(ValueError, match="aov: 'nope' is not one of radiance, albedo"):
        frame.aov("nope")
    with pytest.raises(ValueError, match="reservoir-m needs method restir-di or restir"):
        frame.aov("reservoir-m")
    with pytest.raises(candela.InputError, match="sizes differ|size"):
        candela.metrics.rel_mse(np.zeros((2, 2, 3)), np.zeros((3, 2, 3)))


def test_arrays_have_the_documented_layout(cornell):
    r = candela.Renderer(cornell, method="restir-di", **SMALL)
    frame = r.render_frame()
    for image in (frame.radiance, frame.aov("albedo"), frame.aov("reservoir-m")):
        assert image.shape == (24, 32, 3)
        assert image.dtype == np.float32
        assert image.strides == (32 * 12, 12, 4)
    assert np.shares_memory(frame.radiance, frame.radiance)  # no copy per access
    assert frame.aov("reservoir-m").max() >= 1.0
    stats = frame.stats
    assert stats["rays"] > 0 and stats["non_finite"] == 0
    assert {"gbuffer", "di_candidates", "di_shade"} <= set(stats["stages"])
    r.render_frame()
    with pytest.raises(ValueError, match="no longer the renderer's last frame"):
        frame.aov("albedo")
    for change in (lambda: r.reset_history(), lambda: r.set(spp=2)):
        frame = r.render_frame()
        change()
        with pytest.raises(ValueError, match="no longer the renderer's last frame"):
            frame.aov("albedo")


def test_settings_change_without_a_new_renderer(cornell):
    """set() is the new settings with history reset: the next frame equals a renderer made with them whose
    history was reset at the same frame (random numbers are keyed on the frame index)."""
    r = candela.Renderer(cornell, **SMALL)
    r.render_frame()
    r.set(method="direct", spp=2)
    assert r.settings["method"] == "direct" and r.settings["spp"] == 2
    a = r.render_frame().radiance.copy()
    fresh = candela.Renderer(cornell, method="direct", spp=2, **SMALL)
    fresh.render_frame()
    fresh.reset_history()
    assert np.array_equal(a, fresh.render_frame().radiance)


def test_metrics_are_candela_compare(binary, tmp_path, cornell):
    image = candela.Renderer(cornell, **SMALL).render_frame().radiance
    reference = candela.Renderer(cornell, spp=16, **SMALL).render_frame().radiance
    candela.write_image(str(tmp_path / "a.exr"), image)
    candela.write_image(str(tmp_path / "b.exr"), reference)
    out = subprocess.run([binary, "compare", str(tmp_path / "a.exr"), str(tmp_path / "b.exr")], check=True,
                         capture_output=True, text=True).stdout.split()
    printed = dict(zip(out[0::2], map(float, out[1::2])))
    assert candela.metrics.mse(image, reference) == pytest.approx(printed["mse"], rel=1e-5)
    assert candela.metrics.rel_mse(image, reference) == pytest.approx(printed["rel_mse"], rel=1e-5)
    assert candela.metrics.mean_difference(image, reference) == pytest.approx(printed["mean_difference"], rel=1e-5)
    assert candela.metrics.rel_mse(reference, reference) == 0.0


def test_cameras_set_and_interpolate(cornell):
    a = cornell.camera
    b = candela.Camera((0.0, 1.0, 3.0), (0.0, 1.0, 0.0), fov=60.0)
    mid = candela.Camera.lerp(a, b, 0.5)
    assert mid.position == pytest.approx(tuple((p + q) / 2 for p, q in zip(a.position, b.position)))
    assert mid.fov == pytest.approx((a.fov + 60.0) / 2)
    r = candela.Renderer(cornell, **SMALL)
    first = r.render_frame(camera=b).radiance.copy()
    again = candela.Renderer(cornell, **SMALL).render_frame(camera=b).radiance
    assert np.array_equal(first, again)
    assert not np.array_equal(first, candela.Renderer(cornell, **SMALL).render_frame().radiance)


def resident_kb():
    with open("/proc/self/statm") as f:
        pages = int(f.read().split()[1])
    import resource
    return pages * resource.getpagesize() // 1024


def test_a_thousand_frames_do_not_grow_memory(cornell):
    r = candela.Renderer(cornell, width=16, height=16, method="restir-di", denoise="svgf", accumulate=False)
    for _ in range(100):
        r.render_frame().radiance.sum()
    before = resident_kb()
    for _ in range(1000):
        frame = r.render_frame()
        frame.radiance.sum()
        frame.aov("albedo")
    grown = resident_kb() - before
    assert grown < 4096, f"resident memory grew by {grown} KB over 1000 frames"


def test_frames_render_without_the_gil_and_one_call_at_a_time(manylights):
    """While a frame renders in one thread, another runs Python (the GIL is released) and is refused the
    renderer instead of racing it: the refusal can only happen while render_frame is in flight."""
    import threading
    r = candela.Renderer(manylights, method="restir", width=320, height=180)
    refused = []
    done = threading.Event()

    def render():
        try:
            r.render_frame()
        finally:
            done.set()

    thread = threading.Thread(target=render)
    thread.start()
    while not done.is_set() and not refused:
        try:
            r.settings
        except RuntimeError as e:
            refused.append(str(e))
    thread.join()
    assert refused, "the main thread never ran while the frame rendered, or was let in"
    assert "busy in another thread" in refused[0]
    assert r.frames_rendered == 1
    assert r.settings["method"] == "restir"  # idle again


def test_ctrl_c_stops_a_loop_of_frames(tmp_path):
    """SIGINT while frames render raises KeyboardInterrupt in the loop (once the frame in flight ends); the
    process then exits normally."""
    import os
    import signal
    import sys
    import time
    script = tmp_path / "loop.py"
    script.write_text(
        "import signal, sys\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"  # ignored when started in the background
        "import candela\n"
        "r = candela.Renderer(candela.load_scene('builtin:manylights', lights=64), method='restir-di',\n"
        "                     width=160, height=90)\n"
        "print('rendering', flush=True)\n"
        "try:\n"
        "    while True:\n"
        "        r.render_frame()\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted after', r.frames_rendered, 'frames', flush=True)\n")
    p = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True, env=os.environ.copy())
    assert p.stdout.readline().strip() == "rendering"
    time.sleep(0.5)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=60)
    assert p.returncode == 0
    assert out.startswith("interrupted after")
