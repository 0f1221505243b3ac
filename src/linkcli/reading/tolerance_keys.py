"""The tolerance-design keys of [tolerance] (docs/tolerance.md): general-tolerance classes
in `lengths`, `clearance = "fits"`, [tolerance.cost] and [[tolerance.schemes]]; and the
checks of ISO 286 fits that need the [joints] sizes. Pure Python (`check` runs them).
"""

from __future__ import annotations

from linkcli.io.reader import MISSING, Table
from linkcli.model import CostModel, CostSpec, Scheme
from linkcli.standards import iso286, iso2768

COST_MODELS = ("reciprocal", "reciprocal-power", "exponential", "michael-siddall")
COST_KEYS = ("model", "a", "b", "k", "bounds")
MAX_SCHEMES = 100
GENERAL = 'a general-tolerance class "ISO 2768-m" (f, m, c or v)'
MAX_COST = 1e12  # constants beyond this are typing errors, and overflow the totals


# ---------------------------------------------------------------- lengths and clearance

def read_lengths(t: Table, key: str, links: tuple[str, ...], per_link: tuple[str, ...]):
    """(lengths, general) of `key` in table t: a number (+- on every link), a class
    "ISO 2768-m" (every link), or a table per key of either; keys not named get 0.
    None when absent; (None, None) after an error (recorded)."""
    raw = t.raw(key, None)
    if raw is None:
        return None
    lengths = {k: 0.0 for k in links}
    general: dict[str, str] = {}
    if isinstance(raw, str):
        cls = iso2768.tolerance_class(raw)
        if cls is None:
            t.error(key, f"a tolerance >= 0, {GENERAL}, or a table of either per link", raw)
            return None, None
        return lengths, {k: cls for k in links}
    if isinstance(raw, dict):
        sub = t.table(key)
        if not raw:
            t.error(key, f"a tolerance for at least one of: {', '.join(per_link)}", raw_got="an empty table")
            return None, None
        bad = False
        for link in per_link:
            value = sub.raw(link, MISSING)
            if value is MISSING:
                continue
            if isinstance(value, str):
                cls = iso2768.tolerance_class(value)
                if cls is None:
                    sub.error(link, f"a tolerance >= 0 or {GENERAL}", value)
                    bad = True
                else:
                    general[link] = cls
                continue
            v = sub.number(link, 0.0, nonnegative=True, what=f"a tolerance >= 0 or {GENERAL}")
            bad = bad or v is None
            lengths[link] = v or 0.0
        return (None, None) if bad else (lengths, general)
    v = t.number(key, nonnegative=True, what=f"a tolerance >= 0, {GENERAL}, or a table of either per link")
    return (None, None) if v is None else ({k: v for k in links}, general)


def read_clearance(t: Table) -> tuple[float | None, bool]:
    """(clearance, fits): a radial clearance >= 0, or "fits" (each pin's from its fit)."""
    if t.raw("clearance", None) == "fits":
        return 0.0, True
    return t.number("clearance", 0.0, nonnegative=True,
                    what='a radial clearance >= 0 (length unit) or "fits" (from [joints] fits)'), False


# ---------------------------------------------------------------- [tolerance.cost]

def read_cost(t: Table, per_link: tuple[str, ...], joints: tuple[str, ...]) -> CostSpec | None:
    """[tolerance.cost]: model, a, b, k, bounds for every dimension, and per-key tables (a
    link, or a joint whose fit's hole and shaft it prices) that override them. None when
    absent or bad."""
    c = t.table("cost")
    if c is None:
        return None
    errors = len(c.reader.errors)
    seen: set = set()
    base = _cost_keys(c, seen)
    own: dict[str, CostModel] = {}
    for key in tuple(per_link) + tuple(j for j in joints if j not in per_link):
        sub = c.table(key) if key in c else None
        if sub is not None:
            model = cost_model({**base, **_cost_keys(sub, seen)}, seen)
            if model is not None:
                own[key] = model
    default = cost_model(base, seen) if "model" in base else None
    if len(c.reader.errors) > errors:
        return None
    if default is None and not own:
        c.error("model", f"a cost model for every link (model = one of {', '.join(COST_MODELS)}, with "
                f"a, b, k, bounds) or per link ({per_link[0]} = {{ model = ..., ... }})")
        return None
    return CostSpec(default=default, own=own)


def _cost_keys(t: Table, seen: set) -> dict:
    """The cost keys one table gives, each checked on its own: key -> (value, table)."""
    out = {}
    if "model" in t:
        name = t.string("model", choices=COST_MODELS)
        if name is not None:
            out["model"] = (name, t)
    for key in ("a", "b", "k"):
        if key in t:
            v = t.number(key, nonnegative=True, what=f"a number >= 0 (the cost model's {key})")
            if v is not None and v > MAX_COST:
                t.error(key, f"a constant of at most {MAX_COST:g}", v)
                v = None
            out[key] = (v, t)  # None: given but bad (its line is out; the model is not "missing" it)
    if "bounds" in t:
        b = t.number_list("bounds", length=2, positive=True, what="tolerances [lo, hi] (length unit)")
        if b is not None and not b[0] < b[1]:
            t.error("bounds", "tolerances [lo, hi] with 0 < lo < hi (length unit)", raw_got=f"[{b[0]:g}, {b[1]:g}]")
            b = None
        if b is not None:
            out["bounds"] = ((float(b[0]), float(b[1])), t)
    return out


def cost_model(keys: dict, seen: set) -> CostModel | None:
    """One cost model from merged keys (key -> (value, table that gave it)); each
    complaint once (`seen`). Constants: reciprocal a + b/t (a >= 0, b > 0); reciprocal-power
    a + b/t^k (k > 0); exponential a + b exp(-k t) (k > 0); michael-siddall a t^-k exp(-b t)
    (a > 0, b >= 0, k > 0). bounds = [lo, hi], 0 < lo < hi."""
    if "model" not in keys:
        return None
    name, where = keys["model"]

    def complain(key: str, expected: str, table: Table, got=MISSING) -> None:
        if (table.path, key) not in seen:
            seen.add((table.path, key))
            table.error(key, expected, got)

    values = {"a": 0.0, "k": 1.0}
    if name == "michael-siddall":
        values = {"b": 0.0}
    for key in ("a", "b", "k"):
        if key in keys and keys[key][0] is None:  # a bad value, already reported on its line
            return None
        if key in keys:
            values[key] = keys[key][0]
        elif key not in values:
            complain(key, f"the constant {key} of the {name} cost model ({_formula(name)})", where)
            return None
    bad = None
    if name == "reciprocal" and "k" in keys and keys["k"][0] != 1.0:
        bad = ("k", 'no k other than 1 with model = "reciprocal" ("reciprocal-power" takes k)')
    elif values["b"] <= 0 and name != "michael-siddall":
        bad = ("b", f"b > 0 for the {name} cost model ({_formula(name)})")
    elif values["k"] <= 0:
        bad = ("k", f"k > 0 for the {name} cost model ({_formula(name)})")
    elif name == "michael-siddall" and values["a"] <= 0:
        bad = ("a", f"a > 0 for the michael-siddall cost model ({_formula(name)})")
    if bad is not None:
        key, expected = bad
        complain(key, expected, keys[key][1], keys[key][0])
        return None
    bounds = keys["bounds"][0] if "bounds" in keys else None
    return CostModel(model=name, a=values["a"], b=values["b"], k=values["k"], bounds=bounds)


def _formula(name: str) -> str:
    return {"reciprocal": "a + b / t", "reciprocal-power": "a + b / t^k",
            "exponential": "a + b exp(-k t)", "michael-siddall": "a t^-k exp(-b t)"}[name]


def check_cost_bounds(t: Table, cost: CostSpec, links: tuple[str, ...]) -> None:
    """Every link the allocation chooses needs a cost model with bounds."""
    for link in links:
        model = cost.of(link)
        if model is None:
            t.error("cost", f"a cost model for the {link} (a top-level model, or {link} = {{ ... }})",
                    raw_got=f"none for the {link}")
            return
        if model.bounds is None:
            where = ("cost", link) if link in cost.own else ("cost",)
            t.reader.error(t.path + where + ("bounds",), f"bounds = [lo, hi] for the {link}: the "
                           "tolerances a process can hold (length unit)")
            return


# ---------------------------------------------------------------- [[tolerance.schemes]]

def read_schemes(t: Table, links: tuple[str, ...], per_link: tuple[str, ...],
                 joints: tuple[str, ...] | None) -> tuple[Scheme, ...]:
    """[[tolerance.schemes]]: each a `name` (unique), `fits` (joint -> fit text) and
    `lengths` (as [tolerance] lengths; default 0). () when absent or bad."""
    raw = t.raw("schemes", None)
    if raw is None:
        return ()
    if not isinstance(raw, list) or not raw or not all(isinstance(s, dict) for s in raw):
        t.error("schemes", "an array of tables [[tolerance.schemes]], each with name, fits, lengths", raw)
        return ()
    if len(raw) > MAX_SCHEMES:
        t.error("schemes", f"at most {MAX_SCHEMES} schemes", raw_got=f"{len(raw)}")
        return ()
    out, names = [], set()
    for i, data in enumerate(raw):
        s = Table(t.reader, t.path + (f"schemes[{i}]",), data)
        name = s.string("name", max_len=80)
        if name is not None and name in names:
            s.error("name", "a name no other scheme has", name)
        names.add(name)
        fits = {}
        f = s.table("fits")
        if f is not None:
            for joint in f.keys():
                if joints is not None and joint not in joints:
                    f.raw(joint)
                    f.error(joint, f"a joint: one of {', '.join(joints)}", raw_got=f'joint "{joint}"')
                    continue
                text = f.string(joint, max_len=40)
                if text is not None:
                    fits[joint] = text
        lengths = read_lengths(s, "lengths", links, per_link)
        if lengths is None or lengths[0] is None:  # none, or in error (recorded): its fits still checked
            lengths = ({k: 0.0 for k in links}, {})
        if name is not None:
            out.append(Scheme(name=name, fits=fits, lengths=lengths[0], general=lengths[1]))
    return tuple(out)


# ---------------------------------------------------------------- fits against [joints]

def check_fits(root: Table, tolerance, joints: tuple, units) -> None:
    """Each scheme's fits name joints with a diameter in [joints] and are clearance fits at
    it; clearance = "fits" or schemes want [joints] diameters."""
    if tolerance is None:
        return
    sizes = {j.name: j.diameter for j in joints}
    mm = units.mm_per_length
    for i, scheme in enumerate(tolerance.schemes):
        for joint, text in scheme.fits.items():
            path = ("tolerance", f"schemes[{i}]", "fits", joint)
            if sizes.get(joint) is None:
                root.reader.error(path, f"a diameter for {joint} in [joints] (the fit's nominal size), "
                                  f"e.g. {joint} = {{ diameter = 10 }}", raw_got=f'fit "{text}" and no diameter')
                continue
            problem = iso286.clearance_fit_problem(text, sizes[joint] * mm)
            if problem is not None:
                root.reader.error(path, problem[0], raw_got=problem[1])
    if tolerance.clearance_fits and not any(j.fit for j in joints):
        root.reader.error(("tolerance", "clearance"), 'fits in [joints] for clearance = "fits", e.g. '
                          'A = { diameter = 8, fit = "H7/g6" }', raw_got="no joint with a fit")

