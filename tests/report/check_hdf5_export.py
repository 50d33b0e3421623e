"""Independent check of an HDF5 export (h5py + Python's csv/json modules, no hybridtest code).

Usage: check_hdf5_export.py RUN.h5 RUN.csv [SIDECAR.json]
Reads the CSV with Python, maps every column to its dataset by the layout of
docs/results-format.md, and checks values (bit for bit), units and descriptions (against the
sidecar when given), the /metadata group, the provenance root attributes (every sidecar key
but its channel list, flattened here on their own) and, when RUN.stages.csv exists, the
/stages datasets. Prints every mismatch; exit status 1 if any.
"""
import csv
import json
import math
import os
import re
import sys

import h5py

PHYSICAL = re.compile(r"^(.+)_(command|position|force|lab_time)$")
GROUPS = {"q": "coordinates", "u": "speeds", "r": "restoring_forces"}


def dataset_path(name):
    if name == "t":
        return "/time/t"
    m = PHYSICAL.match(name)
    if m:
        return "/physical/%s/%s" % (m.group(1), m.group(2))
    m = re.match(r"^([qur])([1-9][0-9]*)$", name)
    if m:
        return "/%s/%s" % (GROUPS[m.group(1)], name)
    return "/other/" + name


def flatten(value, name, out):
    """The sidecar's provenance as the exporter should write it: name -> expected value."""
    if isinstance(value, dict) and value:
        for key, item in value.items():
            flatten(item, key if not name else name + "." + key, out)
    elif isinstance(value, list) and value and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        out[name.replace("/", "_")] = [float(v) for v in value]
    elif isinstance(value, list) and value:
        for i, item in enumerate(value):
            flatten(item, "%s.%d" % (name, i), out)
    elif isinstance(value, bool):
        out[name.replace("/", "_")] = "true" if value else "false"
    elif isinstance(value, (int, float, str)):
        out[name.replace("/", "_")] = value
    else:
        out[name.replace("/", "_")] = json.dumps(value, separators=(",", ":"))


def check_columns(h5, csv_path, path_of, errors):
    """Every column of csv_path against its dataset, bit for bit."""
    with open(csv_path, newline="") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], [[float(x) for x in r] for r in rows[1:]]
    for j, name in enumerate(header):
        path = path_of(name)
        if path not in h5:
            errors.append("missing dataset %s for %s" % (path, name))
            continue
        values = h5[path][()]
        if len(values) != len(data) or any(
                not same(float(values[i]), data[i][j]) for i in range(len(data))):
            errors.append("%s differs from column %s of %s" % (path, name, csv_path))


def same(a, b):
    return (math.isnan(a) and math.isnan(b)) or a == b


def main():
    h5_path, csv_path = sys.argv[1], sys.argv[2]
    sidecar = json.load(open(sys.argv[3])) if len(sys.argv) > 3 else None
    with open(csv_path, newline="") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], [[float(x) for x in r] for r in rows[1:]]
    errors = []
    with h5py.File(h5_path, "r") as h5:
        for j, name in enumerate(header):
            path = dataset_path(name)
            if path not in h5:
                errors.append("missing dataset %s for channel %s" % (path, name))
                continue
            ds = h5[path]
            if ds.shape != (len(data),):
                errors.append("%s: shape %s, expected (%d,)" % (path, ds.shape, len(data)))
                continue
            values = ds[()]
            bad = [i for i in range(len(data)) if not same(float(values[i]), data[i][j])]
            if bad:
                i = bad[0]
                errors.append("%s: row %d is %r, CSV says %r (%d rows differ)"
                              % (path, i, float(values[i]), data[i][j], len(bad)))
            if ds.attrs.get("channel") != name:
                errors.append("%s: attribute channel = %r" % (path, ds.attrs.get("channel")))
            for key in ("units", "description"):
                if not isinstance(ds.attrs.get(key), str):
                    errors.append("%s: no string attribute %s" % (path, key))
            if sidecar is not None:
                listed = sidecar["channels"][j]
                if ds.attrs.get("units") != listed["unit"]:
                    errors.append("%s: units %r, sidecar says %r"
                                  % (path, ds.attrs.get("units"), listed["unit"]))
                if ds.attrs.get("description") != listed["description"]:
                    errors.append("%s: description %r, sidecar says %r"
                                  % (path, ds.attrs.get("description"), listed["description"]))
        meta = h5["/metadata"]
        stored = json.loads(meta["sidecar"][()].decode("utf-8"))
        if sidecar is not None:
            if stored != sidecar:
                errors.append("/metadata/sidecar differs from the sidecar file")
            if meta["config"][()].decode("utf-8") != sidecar["config"]:
                errors.append("/metadata/config differs from the sidecar's config text")
            if meta.attrs.get("run_software_version") != sidecar["software_version"]:
                errors.append("/metadata run_software_version mismatch")
        elif stored is not None:
            errors.append("/metadata/sidecar should be null for a run without a sidecar")
        if sidecar is not None:
            expected = {}
            flatten({k: v for k, v in sidecar.items() if k != "channels"}, "", expected)
            for key, want in expected.items():
                got = h5.attrs.get(key)
                if isinstance(want, list):
                    ok = got is not None and list(map(float, got)) == want
                elif isinstance(want, float):
                    ok = got is not None and same(float(got), want)
                else:
                    ok = got == want
                if not ok:
                    errors.append("root attribute %s = %r, sidecar says %r"
                                  % (key, got, want))
            extra = set(h5.attrs.keys()) - set(expected.keys())
            if extra:
                errors.append("root attributes not in the sidecar: %s" % sorted(extra))
        stages = re.sub(r"\.csv$", "", csv_path) + ".stages.csv"
        if os.path.exists(stages):
            check_columns(h5, stages, lambda name: "/stages/" + name.replace("/", "_"), errors)
        elif "stages" in h5:
            errors.append("/stages exists but %s does not" % stages)
        for key in ("format", "software_version", "source_csv"):
            if not isinstance(meta.attrs.get(key), str):
                errors.append("/metadata: no string attribute %s" % key)
    for e in errors:
        print(e)
    print("checked %d channels x %d rows: %s"
          % (len(header), len(data), "FAILED" if errors else "ok"))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
