"""The experiments: each module of this package that defines one registers it here.

A new experiment is one new module with

    @register("name", order=5, help="thesis ...: what it reproduces")
    def run(ctx):           # ctx: runner.Ctx
        ...
        return report.conclude(ctx, rep, run_dirs)

`experiments()` imports every module of the package, so nothing else needs
editing: the command line gets the subcommand, and `all` runs it in `order`.
"""

import importlib
import pkgutil
from dataclasses import dataclass
from typing import Callable

_REGISTERED = {}


@dataclass(frozen=True)
class Experiment:
    name: str       # subcommand and report sub-folder
    run: Callable   # run(ctx) -> path of the report written
    help: str       # one line for --help
    order: int      # position in `all`


def register(name, order, help):
    """Decorator: registers run(ctx) as experiment `name`."""
    def decorate(run):
        if name in _REGISTERED or name == "all":
            raise ValueError(f"experiment {name!r} registered twice (or named `all`, the subcommand for every one)")
        _REGISTERED[name] = Experiment(name, run, help, order)
        return run
    return decorate


def experiments():
    """{name: Experiment} of every module in the package, in `all`'s order."""
    package = importlib.import_module(__package__)
    for module in pkgutil.iter_modules(package.__path__):
        importlib.import_module(f"{__package__}.{module.name}")
    return {e.name: e for e in sorted(_REGISTERED.values(), key=lambda e: (e.order, e.name))}
