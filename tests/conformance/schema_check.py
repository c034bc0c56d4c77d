"""Validates Lottie files against the official schema (PyPI lottie-specs).

    python3 schema_check.py FILE.json...   or   python3 schema_check.py --list LIST.txt

Prints one line per invalid file (the first error with its JSON path) and a summary;
exits 1 when any file is invalid.
"""

import json
import os
import sys

import jsonschema
import lottie_specs


def validator():
    path = os.path.join(os.path.dirname(lottie_specs.__file__), "data", "lottie.schema.json")
    with open(path, encoding="utf-8") as f:
        schema = json.load(f)
    cls = jsonschema.validators.validator_for(schema)
    return cls(schema)


def main(argv):
    files = argv[1:]
    if files[:1] == ["--list"]:
        with open(files[1], encoding="utf-8") as f:
            files = [line.strip() for line in f if line.strip()]
    v = validator()
    bad = 0
    for path in files:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
        err = jsonschema.exceptions.best_match(v.iter_errors(doc))
        if err is not None:
            bad += 1
            where = "/".join(str(p) for p in err.absolute_path)
            print(f"schema: {path}: at /{where}: {err.message[:300]}")
    print(f"schema: {len(files) - bad} of {len(files)} Lottie files valid")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
