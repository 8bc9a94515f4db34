"""Fig 12 (R(t) and a_2(t) for χ = 1, 5, 10) and a small stability diagram, from Python.

    pip install ./python matplotlib        # once, from the repository root
    python examples/python/fig12_stability.py [OUT_DIR]     # default out/python-examples

Everything is computed by the Rust core (the same code as `magbubble figure 12` and
`magbubble stability`); this script only sets parameters and plots. With the fig-12 parameters
every run blows up (a high shape mode meets f_d ≈ 2 f_k, docs/model.md §5): the curves end there.
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import magbubble as mb

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "scenes" / "figures" / "fig12_chi.toml"


def fig12(out: Path) -> None:
    base = mb.Scene.load(SCENE)
    fig, (ax_r, ax_a) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    for chi in [1.0, 5.0, 10.0]:
        run = mb.run(base.with_overrides({"shell.susceptibility": chi}))
        s = run.series
        ended = f", blow-up of {run.blow_up['mode']} at {run.blow_up['t'] * 1e6:.1f} µs" if run.blow_up else ""
        ax_r.plot(s["t"] * 1e6, s["R"] * 1e6, lw=0.8, label=f"χ = {chi:g}{ended}")
        ax_a.plot(s["t"] * 1e6, s["a2"] * 1e6, lw=0.8)
    ax_r.set_ylabel("R [µm]")
    ax_a.set_ylabel("a₂ [µm]")
    ax_a.set_xlabel("t [µs]")
    ax_r.legend(fontsize=8)
    ax_r.set_title("fig 12: coil field, ε_p = 0.5, f_d = 1 MHz, 16 modes")
    fig.tight_layout()
    fig.savefig(out / "fig12.png", dpi=120)
    print("wrote", out / "fig12.png")


def stability_diagram(out: Path) -> None:
    # 8 frequencies, 8 modes: a few seconds. The CSVs stay in out/stability (resumable).
    df = mb.stability(
        SCENE,
        freq="0.4e6:2e6:8:log",
        overrides={"modes.max_order": 8},
        family={"shell.susceptibility": [1, 10]},
        out=out / "stability",
    )
    fig, ax = plt.subplots(figsize=(6, 4))
    for chi, curve in df.groupby("shell.susceptibility"):
        ax.plot(curve["drive.frequency_hz"] / 1e6, curve["critical"], "o-", label=f"χ = {chi:g}")
    ax.set_xscale("log")
    ax.set_xlabel("f_d [MHz]")
    ax.set_ylabel("critical ε_p (Floquet)")
    ax.set_title("stability diagram, 8 modes (missing points: stable up to ε_p = 1)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "stability.png", dpi=120)
    print("wrote", out / "stability.png")
    print(df[["shell.susceptibility", "drive.frequency_hz", "critical", "outcome", "mode"]].to_string(index=False))


if __name__ == "__main__":
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "out" / "python-examples"
    out.mkdir(parents=True, exist_ok=True)
    fig12(out)
    stability_diagram(out)
