"""The examples in examples/python run at a tiny size and write their plots."""
import os
import subprocess
import sys

import pytest

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python")


@pytest.mark.parametrize("script, args", [
    ("equal_time_samplers.py", ["--width", "32", "--height", "18", "--seconds", "0.2", "--reference-spp", "64"]),
    ("sweep_neighbours.py", ["--width", "32", "--height", "18", "--neighbours", "0,2", "--frames", "3",
                             "--seeds", "1", "--reference-spp", "64"]),
])
def test_example_runs_and_plots(tmp_path, script, args):
    plot = tmp_path / "plot.png"
    result = subprocess.run([sys.executable, os.path.join(EXAMPLES, script), "--lights", "64", *args,
                             "--plot", str(plot)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert "wrote" in result.stdout
    with open(plot, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
