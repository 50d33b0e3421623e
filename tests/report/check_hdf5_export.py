"""Independent check of an HDF5 export (h5py + Python's csv/json modules, no hybridtest code).

Usage: check_hdf5_export.py RUN.h5 RUN.csv [SIDECAR.json]
Reads the CSV with Python, maps every column to its dataset by the layout of
docs/results-format.md, and checks values (bit for bit), units and descriptions (against the
sidecar when given) and the /metadata group. Prints every mismatch; exit status 1 if any.
"""
import csv
import json
import math
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
