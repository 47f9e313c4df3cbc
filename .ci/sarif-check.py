#!/usr/bin/env python3
"""Validate SARIF logs against the official SARIF 2.1.0 JSON schema, and check that JUnit XML
files are well-formed with the expected elements.
usage: sarif-check.py SCHEMA.json FILE.sarif|FILE.xml ...   exit 0 when every file passes.
The schema is the one the npm package @microsoft/sarif-multitool ships (sarif-2.1.0.json);
.ci/run installs it, so nothing is copied into this repository."""
import json, sys
import xml.etree.ElementTree as ET

import jsonschema

schema = json.load(open(sys.argv[1]))
validator = jsonschema.validators.validator_for(schema)(schema)
bad = 0
for path in sys.argv[2:]:
    if path.endswith(".xml"):
        try:
            root = ET.parse(path).getroot()
            ok = root.tag == "testsuites" and len(root.findall("testsuite")) >= 1
            print(f"{path}: {'ok' if ok else 'not a JUnit testsuites document'}")
            bad += not ok
        except ET.ParseError as e:
            print(f"{path}: not well-formed: {e}")
            bad += 1
        continue
    errors = list(validator.iter_errors(json.load(open(path))))
    for e in errors[:10]:
        print(f"{path}: {'/'.join(map(str, e.absolute_path))}: {e.message}")
    print(f"{path}: {'ok' if not errors else f'{len(errors)} schema errors'}")
    bad += bool(errors)
sys.exit(1 if bad else 0)
