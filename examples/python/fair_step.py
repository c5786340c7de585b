"""Import a STEP file, fair it, and plot the curvature across a fillet before and after.

    python examples/python/fair_step.py [FILE.step] [-o PLOT.png]

The model's hierarchy (primaries, fillets, corners) is found on import; `fair` sets G2 to the
masters and fairs every surface within the model's tolerances. The plot shows the largest
principal curvature along the middle iso-line across the first connecting surface (its
cross-boundary profile: a fair fillet rises once from each side and falls once).
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import hierfair  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def profile(surface, across, samples=101):
    """The largest principal curvature along the middle iso-line running in `across` ("u" or "v")."""
    (u0, u1), (v0, v1) = surface.domain
    t = np.linspace(0.0, 1.0, samples)
    if across == "u":
        u, v = u0 + (u1 - u0) * t, np.full(samples, 0.5 * (v0 + v1))
    else:
        u, v = np.full(samples, 0.5 * (u0 + u1)), v0 + (v1 - v0) * t
    c = hierfair.Surface.curvature(surface, u, v)
    return t, np.maximum(np.abs(c["k1"]), np.abs(c["k2"]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", nargs="?", default=str(ROOT / "fixtures/occt/occt_plate_boss.step"))
    parser.add_argument("-o", "--output", default="fillet_curvature.png")
    args = parser.parse_args()

    model = hierfair.Model.import_cad(args.file)
    print(model.summary)
    faired, report = model.fair()
    met = sum(1 for link in report["links"] if link.get("met"))
    print(f"{met} of {len(report['links'])} links met")

    fillet = next(name for name in model.names if model.role(name) == "connecting")
    # the fillet's G2 sides: the profile runs across them
    sides = [link["side"] for link in model.links if link["slave"] == fillet]
    across = "u" if sides and sides[0].startswith("u") else "v"
    fig, ax = plt.subplots(figsize=(7, 4))
    for label, m, style in [("input", model, "--"), ("faired", faired, "-")]:
        t, k = profile(m.surface(fillet), across)
        ax.plot(t, k, style, label=label)
    ax.set_xlabel(f"{across} across {fillet} (fraction of its domain)")
    ax.set_ylabel(f"largest principal curvature (1/{model.units})")
    ax.set_title(f"{pathlib.Path(args.file).name}: curvature across {fillet}")
    ax.legend(loc="best")
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
