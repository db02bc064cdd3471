"""Effectors: every disturbance and actuator of the plant, one module each (docs/extending.md).

Every module of this package (except base) is imported here, and its
`@register`ed classes become scenario sections the loader accepts and
effectors the plant builds: adding one is adding a module, nothing else.

- read(root, ctx): every effector section of a scenario -> {kind: config}, in
  the file's order ([disturbances.*] first, then the top-level sections);
- build(configs, body): the enabled ones as effector objects, in that order.
"""
from __future__ import annotations

import importlib
import pkgutil

from .base import ATTITUDE, FORMS, ORBIT, REGISTRY, BodyContext, Effector, Form, Mask, ReadContext, register

__all__ = ["ATTITUDE", "FORMS", "ORBIT", "REGISTRY", "BodyContext", "Effector", "Form", "Mask", "ReadContext",
           "register", "read", "build", "disturbance_kinds"]

for _m in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
    if _m.name != "base" and not _m.name.startswith("_"):
        importlib.import_module(f"{__name__}.{_m.name}")


def disturbance_kinds(registry=None) -> list[str]:
    """Kinds whose section is [disturbances.<kind>], sorted."""
    reg = REGISTRY if registry is None else registry
    return sorted(k for k, c in reg.items() if c.group == "disturbances")


def read(root, ctx: ReadContext) -> dict:
    """Every effector section of the scenario, validated by its own module: {kind: config}."""
    out: dict = {}
    where: dict = {}
    groups = sorted({c.group for c in REGISTRY.values() if c.group})
    for group in groups:
        sec = root.table(group, required=False)
        if sec is None:
            continue
        for name in sec.remaining():
            cls = REGISTRY.get(name)
            if cls is None or cls.group != group:
                known = sorted(k for k, c in REGISTRY.items() if c.group == group)
                sec.fail(sec.key(name), f"unknown key (known {group}: {', '.join(known)})")
            if ctx.kind not in cls.applies_to:
                what = "disturbance" if group == "disturbances" else "effector"
                sec.fail(sec.key(name), f"{what} {name!r} does not apply to a {ctx.kind} scenario")
            out[name] = _read_one(cls, sec.table(name), ctx)
            where[name] = (sec, sec.key(name))
        sec.done()
    _check_conflicts(out, where)
    for kind, cls in REGISTRY.items():
        if cls.group is not None:
            continue
        sec = root.table(kind, required=False)
        if sec is None:
            cfg = cls.default(ctx)
        else:
            if ctx.kind not in cls.applies_to:
                sec.fail(sec.path, f"[{kind}] does not apply to a {ctx.kind} scenario")
            cfg = _read_one(cls, sec, ctx)
            where[kind] = (root, kind)
        if cfg is not None:
            out[kind] = cfg
    _check_conflicts(out, where)
    return out


def _check_conflicts(out: dict, where: dict) -> None:
    for kind, cfg in out.items():
        cls = REGISTRY[kind]
        for other in cls.conflicts:
            if cls.active(cfg) and other in out and REGISTRY[other].active(out[other]):
                sec, key = where[kind]
                sec.fail(key, f"cannot be enabled together with {other}")


def _read_one(cls, sec, ctx):
    cfg = cls.read(sec, ctx)
    sec.done()
    return cfg


def build(configs: dict, body: BodyContext) -> list[Effector]:
    """The effectors of the enabled sections, in the order of `configs`, less the kinds an enabled
    one replaces."""
    on = [kind for kind, cfg in configs.items() if REGISTRY[kind].active(cfg)]
    replaced = {r for kind in on for r in REGISTRY[kind].replaces}
    return [REGISTRY[kind](configs[kind], body) for kind in on if kind not in replaced]
