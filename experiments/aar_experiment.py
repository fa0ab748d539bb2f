#!/usr/bin/python3
"""Reproduce the experiments of Parsons (AFIT, 2017), chapter IV and Appendix A.

Drives the built tools (aar-render, aar-analyze), reads their CSV/JSON outputs
and writes one report folder per experiment: report.md (our numbers beside the
thesis's, with the ratio ours/thesis), PNG plots, the exact command lines,
dataset manifest hashes, software versions and the machine.

  characterization  thesis Experiment 1: Tables 1-3, Figures 15-19
  conops            thesis Experiment 2: Tables 4-5, Figures 20-24; --geometry thesis
                    on the thesis rig, where the receiver's tail leaves the view
  msaa              thesis Experiment 3: Tables 6-11, Figures 25-32
  determinism       thesis Appendix A: Figures 33-34
  realism           beyond the thesis (issue 9): lens distortion, the sensor
                    model, the boom, terrain, propellers and motion blur (when
                    aar-render has them), each alone and all together
  tracking          beyond the thesis: the temporal filter on consecutive
                    frames of a 125 Hz camera with a realistic sensor
  heldout           beyond the thesis: the defaults on realistic scenarios
                    drawn from fixed seeds (path, rig, lens, sensor,
                    background, tanker attitude, propellers, boom)
  all               the seven, in that order (conops on both geometries; with
                    --quick on the default one unless --geometry thesis)

Datasets are rendered into --datasets (default datasets/) and reused: calling
aar-render again on a dataset skips its verified frames. --quick analyzes a
few frames per region/bin so that `all --quick` runs in a few minutes; its
numbers are a smoke test, not a reproduction.

The work lives in the package aar_experiments/ beside this file (its
__init__.py lists the modules): one module per experiment, registered by
name, so a new experiment is one new module there. The thesis's numbers are
in thesis_tables.json.

Only the Python standard library and matplotlib (Debian's python3-matplotlib)
are used. Run from anywhere; commands run in the repository root.
"""

import os
import sys


def _ensure_matplotlib():
    """Re-run under Debian's /usr/bin/python3 when this interpreter lacks matplotlib."""
    try:
        import matplotlib  # noqa: F401
        return
    except ImportError:
        pass
    system_python = "/usr/bin/python3"
    if (os.environ.get("AAR_EXPERIMENT_REEXEC") != "1" and os.path.exists(system_python)
            and os.path.realpath(sys.executable) != os.path.realpath(system_python)):
        os.environ["AAR_EXPERIMENT_REEXEC"] = "1"
        os.execv(system_python, [system_python, os.path.abspath(__file__)] + sys.argv[1:])
    sys.exit("aar_experiment: matplotlib is missing (Debian: apt-get install python3-matplotlib)")


_ensure_matplotlib()

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from aar_experiments import cli  # noqa: E402

if __name__ == "__main__":
    sys.exit(cli.main())
