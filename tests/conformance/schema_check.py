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


def checker():
    """A function from a Lottie document to None (valid) or its first schema error.
    jsonschema-rs decides (the Python jsonschema took most of an hour over the 516 files of
    the conformance run, 2 s for one 3 MB example with jsonschema-rs); the Python
    validator words the error of an invalid file, and decides alone when jsonschema-rs is
    not installed."""
    slow = validator()
    try:
        import jsonschema_rs
        fast = jsonschema_rs.validator_for(slow.schema)
    except ImportError:
        fast = None

    def check(doc):
        if fast is not None and fast.is_valid(doc):
            return None
        err = jsonschema.exceptions.best_match(slow.iter_errors(doc))
        if err is None:
            return None if fast is None else "jsonschema-rs rejects it, Python jsonschema accepts it"
        return f"at /{'/'.join(str(p) for p in err.absolute_path)}: {err.message[:300]}"
    return check


def main(argv):
    files = argv[1:]
    if files[:1] == ["--list"]:
        with open(files[1], encoding="utf-8") as f:
            files = [line.strip() for line in f if line.strip()]
    check = checker()
    bad = 0
    for path in files:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
        err = check(doc)
        if err is not None:
            bad += 1
            print(f"schema: {path}: {err}")
    print(f"schema: {len(files) - bad} of {len(files)} Lottie files valid")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
