"""The hierfair module against closed-form geometry, finite differences and the command line's
results on the repository's fixtures (the same numbers, byte for byte where the command writes
them).

The command line is the workspace's `hier-fair` binary: $HIERFAIR_BIN, else target/debug or
target/release, else built here with cargo.
"""

import doctest
import json
import math
import os
import pathlib
import subprocess
import threading

import numpy as np
import pytest

import hierfair

ROOT = pathlib.Path(__file__).resolve().parents[3]
FIXTURES = ROOT / "fixtures"


def cli():
    """The path of the `hier-fair` binary (built when it is not there)."""
    given = os.environ.get("HIERFAIR_BIN")
    if given:
        return given
    for profile in ("debug", "release"):
        path = ROOT / "target" / profile / "hier-fair"
        if path.exists():
            return str(path)
    subprocess.run(["cargo", "build", "-q", "-p", "hier-fair-cli"], cwd=ROOT, check=True)
    return str(ROOT / "target" / "debug" / "hier-fair")


def run(*args):
    """Runs the command line; its stdout."""
    done = subprocess.run([cli(), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def quarter_cylinder(r=2.0, h=3.0):
    """The exact rational quarter cylinder of radius r and height h (u around, v along z)."""
    w = math.sqrt(0.5)
    ring = [(r, 0.0), (r, r), (0.0, r)]
    points = np.array([[[x, y, z] for z in (0.0, h)] for (x, y) in ring])
    weights = np.array([[1.0, 1.0], [w, w], [1.0, 1.0]])
    return hierfair.Surface((2, 1), ([0, 0, 0, 1, 1, 1], [0, 0, 1, 1]), points, weights)


def sphere_octant(r=1.5):
    """The exact rational sphere octant of radius r: the quarter circle revolved by 90°."""
    w = math.sqrt(0.5)
    profile = [(r, 0.0, 1.0), (r, r, w), (0.0, r, 1.0)]  # (rho, z, weight)
    turn = [((1.0, 0.0), 1.0), ((1.0, 1.0), w), ((0.0, 1.0), 1.0)]
    points, weights = [], []
    for rho, z, wp in profile:
        row, wrow = [], []
        for (cx, cy), wt in turn:
            row.append([rho * cx, rho * cy, z])
            wrow.append(wp * wt)
        points.append(row)
        weights.append(wrow)
    knots = [0, 0, 0, 1, 1, 1]
    return hierfair.Surface((2, 2), (knots, knots), np.array(points), np.array(weights))


def test_a_surface_keeps_its_arrays():
    s = quarter_cylinder()
    assert s.degrees == (2, 1)
    ku, kv = s.knots
    assert ku.tolist() == [0, 0, 0, 1, 1, 1] and kv.tolist() == [0, 0, 1, 1]
    assert s.points.shape == (3, 2, 3)
    assert s.weights.shape == (3, 2)
    assert s.domain == ((0.0, 1.0), (0.0, 1.0))
    back = hierfair.Surface.from_json(s.to_json())
    assert np.array_equal(back.points, s.points)
    assert np.array_equal(back.weights, s.weights)


def test_points_of_the_exact_cylinder_lie_on_it():
    r = 2.0
    s = quarter_cylinder(r)
    u, v = np.meshgrid(np.linspace(0, 1, 17), np.linspace(0, 1, 5), indexing="ij")
    p = s.evaluate(u, v)
    assert p.shape == (17, 5, 3)
    assert np.allclose(np.hypot(p[..., 0], p[..., 1]), r, atol=1e-12)
    g = s.grid(9, 4)
    assert g.shape == (9, 4, 3)
    assert np.allclose(np.hypot(g[..., 0], g[..., 1]), r, atol=1e-12)
    # a scalar pair gives one point
    assert s.evaluate(0.0, 0.0).tolist() == [r, 0.0, 0.0]


def test_curvature_of_the_exact_sphere_and_cylinder():
    r = 1.5
    u = np.linspace(0.05, 0.95, 7)
    c = sphere_octant(r).curvature(u[:, None], u[None, :])
    assert np.allclose(np.abs(c["k1"]), 1 / r, rtol=1e-9)
    assert np.allclose(np.abs(c["k2"]), 1 / r, rtol=1e-9)
    assert np.allclose(c["gauss"], 1 / r**2, rtol=1e-9)
    assert np.allclose(np.linalg.norm(c["normal"], axis=-1), 1.0)
    c = quarter_cylinder(2.0).curvature(u, 0.5)
    assert np.allclose(c["gauss"], 0.0, atol=1e-12)
    assert np.allclose(np.abs(c["mean"]), 0.25, rtol=1e-9)


def test_derivatives_match_finite_differences():
    s = sphere_octant(1.5)
    h = 1e-6
    for u, v in [(0.3, 0.4), (0.7, 0.2)]:
        d = s.derivatives(u, v)
        du = (s.evaluate(u + h, v) - s.evaluate(u - h, v)) / (2 * h)
        dv = (s.evaluate(u, v + h) - s.evaluate(u, v - h)) / (2 * h)
        assert np.allclose(d["du"], du, atol=1e-7)
        assert np.allclose(d["dv"], dv, atol=1e-7)
        duu = (s.derivatives(u + h, v)["du"] - s.derivatives(u - h, v)["du"]) / (2 * h)
        assert np.allclose(d["duu"], duu, atol=1e-6)
    assert set(s.derivatives(0.5, 0.5, order=1)) == {"point", "du", "dv"}


def test_evaluation_gives_the_command_lines_values(tmp_path):
    path = FIXTURES / "surfaces" / "sphere_patch_r50.json"
    want = json.loads(run("eval", path, "--grid", "5,4"))["results"]
    s = hierfair.Surface.from_json(path.read_text())
    u = np.array([r["u"] for r in want])
    v = np.array([r["v"] for r in want])
    d, c = s.derivatives(u, v), s.curvature(u, v)
    for key in ("point", "du", "dv", "duu", "duv", "dvv"):
        assert np.allclose(d[key], [r[key] for r in want], rtol=1e-12, atol=1e-12), key
    assert np.allclose(s.evaluate(u, v), d["point"], rtol=0, atol=0)
    assert np.allclose(c["normal"], [r["normal"] for r in want], atol=1e-12)
    for key in ("k1", "k2", "mean", "gauss"):
        assert np.allclose(c[key], [r[key] for r in want], rtol=1e-12, atol=1e-15), key
    # the grid is the command line's grid
    g = s.grid(5, 4).reshape(-1, 3)
    assert np.allclose(g, [r["point"] for r in want], rtol=1e-12, atol=1e-12)


def test_knot_insertion_and_degree_elevation_keep_the_shape():
    s = sphere_octant()
    u, v = np.meshgrid(np.linspace(0, 1, 11), np.linspace(0, 1, 11), indexing="ij")
    for t in (s.insert_knot("u", 0.3, 2), s.elevate("v", 1), s.insert_knot("v", 0.5)):
        assert np.allclose(t.evaluate(u, v), s.evaluate(u, v), atol=1e-12)
    assert s.elevate("v").degrees == (2, 3)
    assert s.insert_knot("u", 0.3, 2).points.shape[0] == 5


def test_bad_input_is_a_one_line_error():
    with pytest.raises(hierfair.HierFairError, match="points"):
        hierfair.Surface((1, 1), ([0, 0, 1, 1], [0, 0, 1, 1]), np.zeros((2, 2)))
    with pytest.raises(hierfair.HierFairError, match="knots_u"):
        hierfair.Surface((1, 1), ([0, 1, 0.5, 1], [0, 0, 1, 1]), np.zeros((2, 2, 3)))
    with pytest.raises(hierfair.HierFairError, match="no-such-file"):
        hierfair.Model.load("no-such-file.json")
    with pytest.raises(hierfair.HierFairError, match="side"):
        hierfair.continuity(sphere_octant(), "w2", sphere_octant())
    with pytest.raises(hierfair.HierFairError, match="direction"):
        sphere_octant().insert_knot("w", 0.5)
    assert issubclass(hierfair.HierFairError, ValueError)


def test_check_gives_the_command_lines_figures():
    path = FIXTURES / "occt" / "occt_plate_boss.json"
    want = json.loads(run("check", path, "--json"))["links"]
    got = hierfair.Model.load(str(path)).check()
    assert got == want


def test_continuity_of_one_side_is_the_checks():
    m = hierfair.Model.load(str(FIXTURES / "occt" / "occt_plate_boss.json"))
    link = m.links[0]
    got = hierfair.continuity(m.surface(link["slave"]), link["side"], m.surface(link["master"]))
    entry = m.check()[0]
    for key in ("g0", "g1_deg", "g2_rel", "g2_rel_across"):
        assert got[key] == pytest.approx(entry[key], abs=1e-15)


def bezier_patch(z):
    """The bicubic Bézier patch over [0, 1]² with heights z(x, y) at its control points."""
    t = np.linspace(0.0, 1.0, 4)
    net = np.array([[[x, y, z(x, y)] for y in t] for x in t])
    knots = [0.0] * 4 + [1.0] * 4
    return hierfair.Surface((3, 3), (knots, knots), net)


def test_connect_sets_g2_to_a_plane():
    # the plane z = 0 over [0, 1] × [−1, 0]; the slave over [0, 1]² rises from its side y = 0
    plane = bezier_patch(lambda x, y: 0.0)
    plane = hierfair.Surface(
        plane.degrees, plane.knots, plane.points - np.array([0.0, 1.0, 0.0])
    )
    slave = bezier_patch(lambda x, y: 0.3 * y + 0.2 * y * y)
    before = hierfair.continuity(slave, "v0", plane)
    assert before["g1_deg"] > 10.0
    out, sides = hierfair.connect(slave, [("v0", plane)], target="G2")
    assert [s["side"] for s in sides] == ["v0"] and sides[0]["met"]
    after = hierfair.continuity(out, "v0", plane)
    assert after["g0"] < 1e-9 and after["g1_deg"] < 1e-6
    assert after["g2_abs"] < 1e-6
    assert sides[0]["after"]["g1_deg"] == pytest.approx(after["g1_deg"], abs=1e-12)
    with pytest.raises(hierfair.HierFairError, match="masters"):
        hierfair.connect(slave, [plane])


def test_fair_gives_the_command_lines_model_and_report(tmp_path):
    path = FIXTURES / "occt" / "occt_plate_boss.json"
    out, rep = tmp_path / "out.json", tmp_path / "rep.json"
    run("fair", path, "-o", out, "--report", rep, "--quiet")
    faired, report = hierfair.Model.load(str(path)).fair()
    assert faired.to_json() == out.read_text()
    want = json.loads(rep.read_text())
    assert report["links"] == want["links"]
    strip = lambda s: {k: v for k, v in s.items() if k not in ("seconds", "stages")}
    assert [strip(s) for s in report["surfaces"]] == [strip(s) for s in want["surfaces"]]


def _page_data(page):
    """The data a report page embeds (its hf-data element)."""
    start = page.index('id="hf-data">') + len('id="hf-data">')
    return json.loads(page[start:page.index("</script>", start)].replace("<\\/", "</"))


def test_the_report_page_is_the_command_lines(tmp_path):
    path = FIXTURES / "models" / "x_node.json"
    page_path, rep = tmp_path / "r.html", tmp_path / "r.json"
    run("fair", path, "-o", tmp_path / "out.json", "--report", rep, "--html", page_path, "--quiet")
    model = hierfair.Model.load(str(path))
    faired, report = model.fair()
    ours, theirs = _page_data(model.html_report(faired, report)), _page_data(page_path.read_text())
    # the same geometry and links; the report's times differ from run to run
    assert ours["surfaces"] == theirs["surfaces"] and ours["links"] == theirs["links"]
    assert ours["report"]["links"] == json.loads(rep.read_text())["links"]
    checked = _page_data(model.html_report())
    assert checked["kind"] == "check" and checked["checks"]["links"] == model.check()
    with pytest.raises(hierfair.HierFairError, match="faired"):
        model.html_report(hierfair.Model.load(str(FIXTURES / "occt" / "occt_pipe_tee.json")))


def test_fair_takes_tolerances_per_role_in_millimetres(tmp_path):
    path = FIXTURES / "occt" / "occt_pipe_tee.json"
    out = tmp_path / "out.json"
    roles = {"primary": 0.05, "connecting": 0.5, "corner": 0.5}
    args = [a for r, t in roles.items() for a in ("--tolerance-role", f"{r}={t}")]
    run("fair", path, "-o", out, "--quiet", *args)
    faired, _ = hierfair.Model.load(str(path)).fair(tolerance_role=roles)
    assert faired.to_json() == out.read_text()
    with pytest.raises(hierfair.HierFairError, match="tolerance_role"):
        hierfair.Model.load(str(path)).fair(tolerance_role={"fillet": 1.0})


def test_a_cad_file_comes_in_as_the_command_line_reads_it(tmp_path):
    path = FIXTURES / "occt" / "occt_box12_r5.step"
    out = tmp_path / "box.json"
    run("import", path, "-o", out)
    m = hierfair.Model.import_cad(str(path))
    assert m.to_json() == out.read_text()
    assert len(m.names) == 26 and len(m.links) == 48
    assert sorted(set(m.roles.values())) == ["connecting", "corner", "primary"]
    assert "48 links found" in m.summary
    # written as STEP and read back: the same faces and links
    m.export(str(tmp_path / "box.step"))
    back = hierfair.Model.import_cad(str(tmp_path / "box.step"))
    assert len(back.names) == 26 and len(back.links) == 48
    m.save(str(tmp_path / "again.json"))
    assert hierfair.Model.load(str(tmp_path / "again.json")).to_json() == m.to_json()


def test_export_writes_the_command_lines_step_file(tmp_path):
    path = FIXTURES / "occt" / "occt_loft_block.json"
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    run("export", path, "-o", tmp_path / "cli" / "block.step")
    hierfair.Model.load(str(path)).export(str(tmp_path / "py" / "block.step"))
    cli_text = (tmp_path / "cli" / "block.step").read_text()
    assert (tmp_path / "py" / "block.step").read_text() == cli_text
    with pytest.raises(hierfair.HierFairError, match="export writes"):
        hierfair.Model.load(str(path)).export(str(tmp_path / "block.txt"))


def test_fair_surface_gives_the_command_lines_surface(tmp_path):
    path = FIXTURES / "surfaces" / "hood_panel.json"
    out, rep = tmp_path / "out.json", tmp_path / "rep.json"
    run("fair", path, "-o", out, "--report", rep, "--tolerance", "0.5", "--keep", "G2")
    s = hierfair.Surface.from_json(path.read_text())
    faired, report = hierfair.fair_surface(s, tolerance=0.5)
    assert faired.to_json() == out.read_text()
    want = json.loads(rep.read_text())["surfaces"][0]
    for key in ("method", "energy_before", "energy_after", "max_deviation", "iterations"):
        assert report[key] == want[key]
    assert report["energy_after"] < report["energy_before"]


def test_a_method_written_in_python_runs_in_the_framework():
    calls = []

    def halfway(surface, mask, tolerance):
        """Moves every free control point half way to the mean of its four neighbours."""
        calls.append(mask.shape)
        p = surface.points.copy()
        mean = p.copy()
        mean[1:-1, 1:-1] = 0.25 * (p[:-2, 1:-1] + p[2:, 1:-1] + p[1:-1, :-2] + p[1:-1, 2:])
        step = np.where(mask[..., None], 0.5 * (mean - p), 0.0)
        length = np.linalg.norm(step, axis=-1, keepdims=True)
        step *= np.minimum(1.0, 0.99 * tolerance / np.maximum(length, 1e-300))
        return hierfair.Surface(surface.degrees, surface.knots, p + step, surface.weights)

    s = hierfair.Surface.from_json((FIXTURES / "surfaces" / "hood_panel.json").read_text())
    faired, report = hierfair.fair_surface(s, method=halfway, tolerance=0.5)
    assert report["method"] == "halfway"
    assert report["max_control_move"] <= 0.5
    assert calls and faired.points.shape == s.points.shape
    # the X-node: a corner patch linked G2 to four fillets, faired with the Python method
    m = hierfair.Model.load(str(FIXTURES / "models" / "x_node.json"))
    calls.clear()
    faired, report = m.fair(method=halfway)
    assert calls, "the framework never called the method"
    assert all(s["method"] == "halfway" for s in report["surfaces"] if s["processed"])
    assert all(link["met"] for link in report["links"])

    def broken(surface, mask, tolerance):
        raise RuntimeError("no idea")

    with pytest.raises(hierfair.HierFairError, match="no idea"):
        hierfair.fair_surface(s, method=broken)


def test_long_calls_let_other_threads_run():
    m = hierfair.Model.load(str(FIXTURES / "occt" / "occt_pipe_tee.json"))
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(1)
            done.wait(0.001)

    t = threading.Thread(target=tick)
    t.start()
    m.fair()
    done.set()
    t.join()
    # the fairing takes a fraction of a second; a thread holding the GIL would have starved
    # the ticker for all of it
    assert len(ticks) > 5


def test_the_methods_are_listed():
    names = [m["name"] for m in hierfair.methods()]
    assert "energy" in names and "krr" in names


def test_the_docstring_examples_run(monkeypatch):
    # the examples name the fixtures from the repository's root
    monkeypatch.chdir(ROOT)
    failures, _ = doctest.testmod(hierfair)
    assert failures == 0
    parser, runner = doctest.DocTestParser(), doctest.DocTestRunner()
    owners = [hierfair.Surface, hierfair.Model]
    documented = [hierfair.fair_surface, hierfair.connect, hierfair.continuity, hierfair.methods]
    for owner in owners:
        documented += [getattr(owner, n) for n in dir(owner) if not n.startswith("_")]
    documented.append(hierfair.Surface)
    examples = 0
    for obj in documented:
        text = getattr(obj, "__doc__", None) or ""
        if ">>>" not in text:
            continue
        test = parser.get_doctest(text, {}, getattr(obj, "__qualname__", str(obj)), None, 0)
        examples += len(test.examples)
        runner.run(test)
    assert runner.failures == 0
    # every method of the two classes that computes something shows how
    assert examples >= 40
