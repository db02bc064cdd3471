"""`aocs gains`: regenerate every gain design from tools/gains.toml into the
firmware tables (firmware/gains/aocs_gains.{h,c}) and their registration
(firmware/gains/gain_tables.def: table ids, names, laws), the report
(docs/gains/) and optionally a JSON summary; `--check` compares with the
committed files."""
from __future__ import annotations

import argparse
import difflib
import hashlib
import json
import re
import sys
import tempfile
from pathlib import Path

from aocs_design import designs, models
from aocs_design.checks import DesignError
from aocs_gains import report, tables

REPO = Path(__file__).resolve().parents[2]
DEFAULT_CONFIG = REPO / "tools" / "gains.toml"
DEFAULT_OUT = REPO / "firmware" / "gains"
DEFAULT_REPORT = REPO / "docs" / "gains"

_CACHE: dict[str, tuple[list, dict[str, str]]] = {}


class GainsConfigError(ValueError):
    """The design configuration cannot be read or lacks what a design needs (one line, naming file and key)."""


def load_config(path: Path) -> dict:
    import tomllib  # deferred: only when a design file is read

    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except FileNotFoundError:
        raise GainsConfigError(f"{path}: no such design configuration file") from None
    except IsADirectoryError:
        raise GainsConfigError(f"{path}: is a folder, not a design configuration file") from None
    except UnicodeDecodeError as exc:
        raise GainsConfigError(f"{path}: not UTF-8 text (byte {exc.start})") from None
    except tomllib.TOMLDecodeError as exc:
        raise GainsConfigError(f"{path}: not valid TOML: {exc}") from None


def design_all(cfg: dict) -> list:
    """Every design of the config, in file order; raises DesignError on any failed check."""
    plants = cfg["plants"]
    return [designs.design_one(name, d, plants[d["plant"]], cfg.get("hinf", {}))
            for name, d in cfg["designs"].items()]


def defines(cfg: dict) -> list[tuple[str, float, str]]:
    pl = cfg["plants"]
    out = []
    for i, v in enumerate(pl["irassi"]["inertia_diag"]):
        out.append((f"AOCS_GAINS_IRASSI_J{i + 1}{i + 1}_KGM2", v, "lqr_quat design inertia, SPEC 4 irassi"))
    ls = pl["landsat8"]
    out += [("AOCS_GAINS_LANDSAT8_MASS_KG", ls["mass"], "orbit_lqr design mass"),
            ("AOCS_GAINS_LANDSAT8_RADIUS_M", ls["radius"], "orbit radius"),
            ("AOCS_GAINS_LANDSAT8_MU_M3PS2", ls["mu"], "gravitational parameter"),
            ("AOCS_GAINS_LANDSAT8_N_RADPS", models.mean_motion(ls["mu"], ls["radius"]),
             "mean motion sqrt(mu / R^3), SPEC 2.8")]
    geo = pl["geo"]
    for axis, v in zip("XYZ", geo["inertia_diag"]):
        out.append((f"AOCS_GAINS_GEO_I{axis}_KGM2", v, "hinf design inertia, SPEC 2.6"))
    out.append(("AOCS_GAINS_GEO_W0_RADPS", geo["w0"], "orbit rate, SPEC 2.6"))
    return out


def generate(config: Path) -> tuple[list, dict[str, str]]:
    """Designs and the text of the two table files; cached per config content."""
    cfg = load_config(config)
    key = hashlib.sha256(Path(config).read_bytes()).hexdigest()
    if key not in _CACHE:
        try:
            designs = design_all(cfg)
        except GainsConfigError as exc:
            raise GainsConfigError(f"{config}: {exc}") from None
        except KeyError as exc:
            raise GainsConfigError(f"{config}: missing key {exc.args[0]!r} (tools/gains.toml shows every key)") from None
        except (TypeError, ValueError, AttributeError) as exc:
            raise GainsConfigError(f"{config}: a value of the wrong type or size ({exc})") from None
        files = {tables.HEADER_NAME: tables.emit_header(designs, defines(cfg)),
                 tables.SOURCE_NAME: tables.emit_source(designs),
                 tables.REGISTRY_NAME: tables.emit_registry(designs)}
        _CACHE[key] = (designs, files)
    return _CACHE[key]


def summary(designs) -> dict:
    out = {}
    for d in designs:
        e = {"kind": d.inputs["kind"], "K": d.k.tolist(),
             "closed_loop_poles": [[float(p.real), float(p.imag)] for p in d.poles],
             "slowest_pole_re": d.slowest_pole_re}
        if hasattr(d, "residual_rel"):
            e["are_residual"] = d.residual_abs
            e["are_residual_rel"] = d.residual_rel
        else:
            # gamma: the LMI's gamma of the chosen K; gamma_star: the minimum of this design's own
            # LMI (step 1); gamma_min: the minimum of the plain SPEC 2.6 LMI
            e.update({"gamma": d.gamma, "gamma_star": d.gamma_star, "gamma_min": d.gamma_min,
                      "form": d.form, "hinf_norm_check": d.hinf_norm, "lmi_max_eig": d.lmi_max_eig,
                      "lmi_min_eig": d.lmi_min_eig, "k_rel_diff_clarabel_scs": d.k_rel_diff})
        out[d.name] = e
    return out


# Numbers in the tables may move in their last digits between machines (a
# different BLAS kernel in the Riccati or conic solver); everything else must
# be identical. Table entries (the AOCS_R(...) literals) must agree within
# TABLE_RTOL of the largest entry of their line. The LMI designs are the
# loosest: the interior-point solvers stop at ~1e-8 on the duality gap, and
# the K recovered from the LMI variables (K = Y X^-1, an ill-conditioned X)
# moved by 6.5e-6 of its line's largest entry between the Intel machine the
# tables were made on and an AMD EPYC with the same pinned packages
# (hinf_bounded, row 1). 1e-4 passes that with a margin of 15 and is still
# far below what a change of a design input does to K (alpha_sel 1% higher
# moves the tables' lines by up to 1e-2); the design inputs themselves are
# compared character for character. The solver statistics of the provenance
# comments (residuals, gamma, poles: always printed in exponent notation) may
# differ; every other character may not.
TABLE_RTOL = 1e-4
_LITERAL = re.compile(r"AOCS_R\(([^)]*)\)")
_STATISTIC = re.compile(r"[-+]?\d+\.?\d*[eE][-+]?\d+")


def _shape(line: str) -> str:
    return _STATISTIC.sub("#", _LITERAL.sub("AOCS_R(#)", line))


def _line_difference(a: str, b: str) -> float:
    """Largest relative difference of the table entries of two lines of the same shape
    (0 for identical lines, statistics only differing); inf when anything else differs."""
    if a == b:
        return 0.0
    if _shape(a) != _shape(b):
        return float("inf")
    va = [float(x) for x in _LITERAL.findall(a)]
    vb = [float(x) for x in _LITERAL.findall(b)]
    if len(va) != len(vb):
        return float("inf")
    if not va:
        return 0.0
    scale = max(max(abs(x) for x in va), 1e-300)
    return max(abs(x - y) for x, y in zip(va, vb)) / scale


def _numeric_match(old: str, fresh: str) -> tuple[bool, float]:
    """(same up to number noise, largest relative difference of a table entry)."""
    old_lines, new_lines = old.splitlines(), fresh.splitlines()
    if len(old_lines) != len(new_lines):
        return False, float("inf")
    worst = max((_line_difference(a, b) for a, b in zip(old_lines, new_lines)), default=0.0)
    return worst <= TABLE_RTOL, worst


def _real_changes(old: str, fresh: str, path: Path, name: str) -> list[str]:
    """Diff lines of the changes beyond number noise only (noise elsewhere in the file, from another
    machine's BLAS, is not a change and is not shown)."""
    old_lines, new_lines = old.splitlines(), fresh.splitlines()
    if len(old_lines) != len(new_lines):
        return list(difflib.unified_diff(old_lines, new_lines, str(path), f"regenerated/{name}",
                                         lineterm="", n=0))
    out = [f"--- {path}", f"+++ regenerated/{name}"]
    for i, (a, b) in enumerate(zip(old_lines, new_lines), start=1):
        if _line_difference(a, b) > TABLE_RTOL:
            out += [f"@@ -{i} +{i} @@", f"-{a}", f"+{b}"]
    return out


def check(files: dict[str, str], committed_dir: Path) -> tuple[list[str], list[str]]:
    """(problems, notes): problems empty when every table matches its design,
    bit for bit or within TABLE_RTOL (then a note says so)."""
    problems, notes = [], []
    with tempfile.TemporaryDirectory(prefix="aocs-gains-") as tmp:
        for name, text in files.items():
            (Path(tmp) / name).write_text(text)
            fresh = (Path(tmp) / name).read_text()
            path = committed_dir / name
            if not path.exists():
                problems.append(f"{path}: missing (run `aocs gains`)")
                continue
            old = path.read_text()
            if old == fresh:
                continue
            same, worst = _numeric_match(old, fresh)
            if same:
                notes.append(f"{path}: not bit-for-bit, table entries agree within "
                             f"{worst:.1e} relative (tolerance {TABLE_RTOL:.0e})")
                continue
            diff = _real_changes(old, fresh, path, name)
            changed = sum(1 for ln in diff if ln[:1] in "+-" and not ln.startswith(("+++", "---")))
            problems.append(f"{path}: differs from its design ({changed} changed lines)\n"
                            + "\n".join(diff[:40]))
    return problems, notes


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--config", type=Path, default=DEFAULT_CONFIG, help="design config (TOML)")
    parser.add_argument("--out-dir", type=Path, default=DEFAULT_OUT, help="where the C tables go")
    parser.add_argument("--report-dir", type=Path, default=DEFAULT_REPORT, help="report.md + PNGs")
    parser.add_argument("--no-report", action="store_true", help="do not write the report")
    parser.add_argument("--json", type=Path, metavar="FILE", help="write a per-design JSON summary")
    parser.add_argument("--check", action="store_true",
                        help="regenerate in a temp dir and compare with the tables in --out-dir "
                             "(bit for bit; table entries may differ by 1e-6 relative, "
                             "solver noise across machines); exit 1 otherwise, write nothing")


def run(args: argparse.Namespace) -> int:
    try:
        designs, files = generate(args.config)
    except GainsConfigError as exc:
        print(f"aocs gains: error: {exc}", file=sys.stderr)
        return 2
    except DesignError as exc:
        print(f"aocs gains: FAILED: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 2
    if args.json:
        Path(args.json).write_text(json.dumps(summary(designs), indent=2) + "\n")
    if args.check:
        problems, notes = check(files, Path(args.out_dir))
        for note in notes:
            print(f"aocs gains --check: {note}")
        if problems:
            print("aocs gains --check: committed tables differ from their designs:", file=sys.stderr)
            for p in problems:
                print(p, file=sys.stderr)
            return 1
        print(f"aocs gains --check: {', '.join(files)} match tools/gains.toml ({len(designs)} designs)")
        return 0
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (out / name).write_text(text)
    if not args.no_report:
        report.write(designs, Path(args.report_dir))
    for d in designs:
        val = (f"ARE residual {d.residual_abs:.2e}" if hasattr(d, "residual_rel")
               else f"gamma {d.gamma:.6e}, H-inf norm {d.hinf_norm:.6e}")
        print(f"{d.name:18s} {val:48s} slowest pole Re {d.slowest_pole_re:.4e}")
    return 0
