"""How the table report lays out the dynamics sections (docs/dynamics.md): units in the labels
and headings, the history with one magnitude column per pin (the components are in JSON, TOML
and CSV). Pure Python: the report draws these blocks (linkcli.io.tables)."""

from __future__ import annotations

SECTIONS = ("simulation", "history", "events", "energy", "flywheel", "balance")


def report_tables(name: str, section, lu: str, au: str) -> list:
    from linkcli.io.tables import KeyValues, Rows
    if name == "simulation" and isinstance(section, dict):
        units = {"start": au, "end_angle": au, "end_time": "s", "stop_time": "s", "end_speed": f"{au}/s",
                 "stop_speed": f"{au}/s", "flywheel_inertia": "kg m2"}
        rows = []
        for k, v in section.items():
            if k == "drives":  # several drives: each one's start and end
                drive_units = {"start_angle": au, "start_speed": f"{au}/s", "end_angle": au,
                               "end_speed": f"{au}/s", "flywheel_inertia": "kg m2"}
                for drive, values in v.items():
                    rows += [(f"{drive} {key.replace('_', ' ')}" + (f" ({drive_units[key]})" if key in drive_units else ""), x)
                             for key, x in values.items()]
            elif k == "start":
                rows += [(f"start angle ({au})", v["angle"]), (f"start speed ({au}/s)", v["speed"])]
            elif k == "friction":
                rows += [("friction coefficient", v["coefficient"]),
                         (f"friction sign smoothed below ({au}/s)", v["regularization_speed"])]
            else:
                rows.append((k.replace("_", " ") + (f" ({units[k]})" if k in units else ""), v))
        return [KeyValues("Simulation", rows)]
    if name == "history" and isinstance(section, list) and section:
        heads = {"time": "time (s)", "angle": f"angle ({au})", "speed": f"speed ({au}/s)",
                 "acceleration": f"accel. ({au}/s2)", "drive_torque": "drive (N m)"}
        base = tuple(heads)
        several = "drives" in section[0]
        if several:  # a column per drive and quantity
            heads = {"time": "time (s)"}
            for drive in section[0]["drives"]:
                heads.update({f"{drive} {k}": f"{drive} {h}" for k, h in (
                    ("angle", f"({au})"), ("speed", f"speed ({au}/s)"), ("acceleration", f"accel. ({au}/s2)"),
                    ("torque", "torque (N m)"))})
        rows = []
        for r in section:
            if several:
                row = {"time": r["time"]}
                for drive, values in r["drives"].items():
                    row.update({f"{drive} {k}": v for k, v in values.items()})
            else:
                row = {k: r.get(k) for k in base}
            for pin, force in r.get("pins", {}).items():
                row[f"pin {pin}"] = force["magnitude"]
                heads.setdefault(f"pin {pin}", f"{pin} (N)")
            for element, force in r.get("elements", {}).items():
                row[f"element {element}"] = force
                heads.setdefault(f"element {element}", element)
            rows.append(row)
        return [Rows("History (pin force magnitudes; element forces in N or N m)", rows, heads)]
    if name == "events" and isinstance(section, list) and not section:
        return [KeyValues("Events", [("events", "none")])]
    if name == "events" and isinstance(section, list) and section:
        heads = {"event": "event", "time": "time (s)", "angle": f"angle ({au})", "speed": f"speed ({au}/s)"}
        if any("drives" in r for r in section):  # several drives: per drive
            heads = {"event": "event", "drive": "drive", "time": "time (s)"}
            rows = []
            for r in section:
                row = {"event": r["event"], "drive": r.get("drive", ""), "time": r["time"]}
                for drive, values in r["drives"].items():
                    for key, unit in (("angle", au), ("speed", f"{au}/s")):
                        row[f"{drive} {key}"] = values[key]
                        heads.setdefault(f"{drive} {key}", f"{drive} {key} ({unit})")
                rows.append(row)
            return [Rows("Events", rows, heads)]
        return [Rows("Events", section, heads)]
    if name == "energy" and isinstance(section, dict):
        rows = [(f"{k.replace('_', ' ')} (J)", v) for k, v in section.items() if k != "start"]
        rows += [(f"{k} at the start (J)", v) for k, v in section.get("start", {}).items()]
        return [KeyValues("Energy at the end (potential from the start)", rows)]
    if name == "flywheel" and isinstance(section, dict):
        labels = {"fluctuation": "coefficient of fluctuation Cs", "mean_speed": f"mean speed ({au}/s)",
                  "mean_torque": "mean drive torque (N m)", "energy_fluctuation": "energy fluctuation (J)",
                  "inertia": "inertia needed on the drive (kg m2)",
                  "added_inertia": "flywheel to add (kg m2)"}
        rows = [(labels.get(k, k), v) for k, v in section.items() if not isinstance(v, dict) and v is not None]
        inertia = section.get("linkage_inertia") or {}
        rows += [(f"generalized inertia M {k} (kg m2)", v) for k, v in inertia.items()]
        for key, title in (("as_given", "as given"), ("with_flywheel", "with the flywheel")):
            run = section.get(key)
            if run is None:
                rows.append((f"{title}: steady cycle", "none (stalls or runs away)"))
                continue
            rows += [(f"{title}: max speed ({au}/s)", run["max_speed"]), (f"{title}: min speed ({au}/s)", run["min_speed"]),
                     (f"{title}: fluctuation (integrated)", run["fluctuation"])]
        return [KeyValues("Flywheel (energy method, checked by integration)", rows)]
    if name == "balance" and isinstance(section, dict):
        blocks = [KeyValues("Balance", [(f"drive speed ({au}/s)", section.get("speed")),
                                        ("rows over the cycle", section.get("rows"))])]
        cases = [k for k in ("unbalanced", "balanced") if k in section]
        rows = []
        for what, label, unit in (("shaking_force", "shaking force", "N"), ("shaking_moment", "shaking moment", "N m"),
                                  ("input_torque", "input torque", "N m")):
            for stat in ("max", "rms"):
                rows.append({"quantity": f"{label} {stat} ({unit})", **{c: section[c][what][stat] for c in cases}})
            rows.append({"quantity": f"{label} at input ({au})", **{c: section[c][what]["at_input"] for c in cases}})
        for pin in section["unbalanced"]["pins"]:
            rows.append({"quantity": f"pin {pin} max (N)", **{c: section[c]["pins"][pin] for c in cases}})
        blocks.append(Rows("Shaking and loads over the cycle", rows))
        cycle = section.get("cycle") or []
        if cycle:
            heads = {"input": f"input ({au})"}
            rows = []
            for r in cycle:
                row = {"input": r["input"]}
                for c in cases:
                    row[f"{c} force"] = r[c]["shaking_force"]["magnitude"]
                    row[f"{c} moment"] = r[c]["shaking_moment"]
                    heads[f"{c} force"] = f"|F| {c} (N)"
                    heads[f"{c} moment"] = f"M {c} (N m)"
                rows.append(row)
            blocks.append(Rows("Shaking force and moment over the cycle", rows, heads))
        if "counterweights" in section:
            heads = {"link": "link", "mass_radius": f"mass x radius (kg {lu})", "angle": f"angle ({au})",
                     "radius": f"radius ({lu})", "mass": "mass (kg)"}
            blocks.append(Rows("Counterweights (angle in the link's frame)",
                               [{"link": k, **v} for k, v in section["counterweights"].items()], heads))
        return blocks
    return []
