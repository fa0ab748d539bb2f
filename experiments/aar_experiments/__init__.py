"""The thesis's experiments (Parsons 2017, chapter IV and Appendix A) and the realism experiment beyond them,
run by experiments/aar_experiment.py.

  thesis            the thesis's layout and numbers (experiments/thesis_tables.json)
  runner            running aar-render and aar-analyze, the analysis cache, provenance
  outputs           reading the tools' CSV and JSON outputs
  report            report.md: tables, ours beside the thesis's, commands, software and machine
  plots             the PNG figures (matplotlib)
  registry          the experiments, one module each, registered by name:
    characterization  thesis Experiment 1 (with shelled_vs_full, the skeleton it shares with conops)
    conops            thesis Experiment 2
    msaa              thesis Experiment 3
    determinism       thesis Appendix A
    realism           beyond the thesis: each realism effect alone and together (with realism_report)
    tracking          beyond the thesis: the temporal filter at a camera's rate (125 Hz)
    heldout           beyond the thesis: realistic scenarios drawn from fixed seeds
  cli               the command line: a subcommand per registered experiment, and `all`
"""
