"""What the example scripts share: their output folder, their command line, saving a figure,
the block of the rigid-model examples and the run of the stick-slip examples.

The scripts import it as ``from _common import ...`` (``python examples/NAME.py`` puts this
folder first on ``sys.path``).
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path

from friction_model.contact.laws import ExponentialLaw
from friction_model.dynamics.rigid import BlockParams

#: Where the examples write: ``examples/out/NAME``.
OUT_ROOT = Path(__file__).parent / "out"


def example_arguments(
    argv: Sequence[str] | None,
    doc: str,
    name: str,
    *,
    seed: int | None = None,
    seed_help: str = "random seed",
) -> argparse.Namespace:
    """Parse the command line of an example script and create its output folder.

    Parameters
    ----------
    argv : sequence of str or None
        The arguments (``None``: ``sys.argv[1:]``).
    doc : str
        The script's docstring; its first line describes the script in ``--help``.
    name : str
        Default output folder ``examples/out/NAME`` (option ``--out``).
    seed : int, optional
        Default of the option ``--seed`` (no such option when omitted).
    seed_help : str
        Help line of ``--seed``.

    Returns
    -------
    argparse.Namespace
        ``out`` (a :class:`~pathlib.Path`, created) and, with `seed`, ``seed``.
    """
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT_ROOT / name, help="output folder")
    if seed is not None:
        parser.add_argument("--seed", type=int, default=seed, help=seed_help)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    return args


def save_figure(fig, path: Path) -> None:
    """Lay `fig` out tightly, write it to `path` at 130 dpi and close it."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def face_contact_block() -> tuple[BlockParams, ExponentialLaw]:
    """The rigid-model examples' block and friction law (the scenario of
    ``tests/test_rigid.py``): four 4.55 mm elements on face contact, c_N = 5e4 N/m, and
    Eq. 5.7 with a1 = 0.2, a2 = 0.15, a3 = -0.3 s/m."""
    params = BlockParams(
        n_elements=4,
        element_length_m=4.55e-3,
        contact_model="face",
        contact_stiffness_N_m=5e4,
    )
    return params, ExponentialLaw(a1=0.2, a2=0.15, a3=-0.3)


