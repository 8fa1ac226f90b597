# Converts the optical-glass shelves of the refractiveindex.info database
# (public domain, CC0 1.0) into the compact catalogues of lens-data/glass/,
# one JSON file per vendor. Rerunnable: the database ships in several PyPI
# packages; by default this reads the copy inside the optiland wheel
# (`pip install optiland`, database/data-nk/glass/VENDOR/NAME.yml), or give
# the path of any `data-nk/glass` folder:
#
#   python3 tools/convert_glass.py [PATH/TO/data-nk/glass]
#
# Each glass keeps its dispersion formula exactly as the database gives it
# (refractiveindex.info formulas 1-9, coefficients as written, wavelength in
# micrometres), or its tabulated n; its valid range (converted to nm); and
# the vendor's nd and vd where the database has them. The source, licence
# and the catalogue's date (from the vendor catalogue the database cites)
# are written into each file.
import collections, glob, json, os, re, sys

import yaml


def default_dir():
    import optiland
    return os.path.join(os.path.dirname(optiland.__file__), "database", "data-nk", "glass")


def numbers(s):
    return [float(x) for x in str(s).split()]


def glass(path):
    d = yaml.safe_load(open(path, encoding="utf-8"))
    entry = None
    for e in d.get("DATA", []):
        t = e["type"].strip()
        if t.startswith("formula "):
            lo, hi = numbers(e["wavelength_range"])
            entry = {"formula": "rii " + t.split()[1], "coefficients": numbers(e["coefficients"]),
                     "range_nm": [round(lo * 1e3, 6), round(hi * 1e3, 6)]}
            break
        if t in ("tabulated n", "tabulated nk"):
            rows = [numbers(r) for r in e["data"].strip().splitlines() if r.strip()]
            rows = [[round(r[0] * 1e3, 6), r[1]] for r in rows]
            entry = {"formula": "tabulated", "data_nm_n": rows, "range_nm": [rows[0][0], rows[-1][0]]}
            break
    if entry is None:
        return None, None
    specs = d.get("SPECS", {}) or {}
    for key, name in (("nd", "nd"), ("Vd", "vd")):
        if isinstance(specs.get(key), (int, float)):
            entry[name] = specs[key]
    ref = str(d.get("REFERENCES", "")).replace("<br>", "; ")
    ref = re.sub(r"<[^>]+>", "", ref).strip()
    return entry, ref


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else default_dir()
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "lens-data", "glass")
    os.makedirs(out, exist_ok=True)
    total = 0
    for vendor_dir in sorted(glob.glob(os.path.join(src, "*"))):
        vendor = os.path.basename(vendor_dir).upper()
        glasses, refs = {}, collections.Counter()
        for path in sorted(glob.glob(os.path.join(vendor_dir, "**", "*.yml"), recursive=True)):
            name = os.path.splitext(os.path.basename(path))[0]
            if name in glasses:
                continue
            entry, ref = glass(path)
            if entry is None:
                continue
            entry["name"] = name
            glasses[name] = (entry, ref)
            refs[ref] += 1
        if not glasses:
            continue
        common = refs.most_common(1)[0][0]
        rows = []
        for name in sorted(glasses):
            entry, ref = glasses[name]
            if ref != common:
                entry["reference"] = ref
            rows.append(dict(sorted(entry.items(), key=lambda kv: kv[0] != "name")))
        date = re.search(r"(\d{4}-\d{2}(-\d{2})?)", common)
        catalog = {
            "catalog": vendor,
            "source": "refractiveindex.info database, shelf glass/" + os.path.basename(vendor_dir) + ": " + common,
            "license": "CC0-1.0 (public domain)",
            "catalog_date": date.group(1) if date else None,
            "wavelength_unit_of_coefficients": "micrometre",
            "glasses": rows,
        }
        # one glass a line: compact, and a diff shows which glasses changed
        head = json.dumps({k: v for k, v in catalog.items() if k != "glasses"}, indent=1)[:-2]
        body = ",\n".join(json.dumps(g, separators=(",", ":")) for g in rows)
        with open(os.path.join(out, vendor + ".json"), "w", encoding="utf-8") as f:
            f.write(head + ',\n "glasses": [\n' + body + "\n]}\n")
        total += len(rows)
        print(f"{vendor}: {len(rows)} glasses")
    print(f"{total} glasses in {out}")


if __name__ == "__main__":
    main()
