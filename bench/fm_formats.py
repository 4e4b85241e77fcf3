"""Benchmark: reading and writing feature models in .fm, UVL and FeatureIDE XML.

For every model it times, best of ``--repeat``: importing the file, writing it as .fm,
UVL and FeatureIDE XML, and parsing each written text back; it prints a markdown table.
With ``--flamapy-python`` it also has flamapy (in its own virtualenv, see
bench/fm_analysis.py) read our UVL and XML exports and checks it sees the same number
of features and constraints, so the exports are known to open in a second tool:

    /tmp/venv/bin/python bench/fm_formats.py [--repeat 3]
        [--flamapy-python /tmp/benchvenv/bin/python] [MODEL ...]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "feature-models"
FLAMAPY_READ = """
import json, sys
from flamapy.metamodels.fm_metamodel.transformations import UVLReader, FeatureIDEReader
path = sys.argv[1]
model = (UVLReader if path.endswith(".uvl") else FeatureIDEReader)(path).transform()
print(json.dumps([len(model.get_features()), len(model.get_constraints())]))
"""


def best(repeat: int, action):
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = action()
        times.append(time.perf_counter() - start)
    return min(times), result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("models", nargs="*", type=Path)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--flamapy-python")
    args = parser.parse_args()

    from spl.dsl.fm import language as fm
    from spl.dsl.fm.printer import print_model
    from spl.dsl.interop.featureide import parse_featureide
    from spl.dsl.interop.featureide_writer import write_featureide
    from spl.dsl.interop.formats import load_feature_model
    from spl.dsl.interop.uvl import parse_uvl, write_uvl

    models = args.models or sorted([*DATA.glob("*.uvl"), *DATA.glob("*.xml")])
    print(
        "| model | features | import | write .fm | parse .fm | write UVL | parse UVL "
        "| write XML | parse XML | flamapy reads exports |"
    )
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |")
    failures = 0
    for path in models:
        load_time, model = best(args.repeat, lambda p=path: load_feature_model(p))
        features = sum(1 for _ in fm.all_features(model))
        row = [path.name, str(features), f"{load_time:.3f}"]
        fm_write, fm_text = best(args.repeat, lambda m=model: print_model(m))
        fm_parse, _ = best(args.repeat, lambda t=fm_text: fm.parse_text(t))
        uvl_write, uvl_text = best(args.repeat, lambda m=model: write_uvl(m))
        uvl_parse, _ = best(args.repeat, lambda t=uvl_text: parse_uvl(t))
        try:
            xml_write, xml_data = best(args.repeat, lambda m=model: write_featureide(m))
            xml_parse, _ = best(args.repeat, lambda d=xml_data: parse_featureide(d))
            xml = [f"{xml_write:.3f}", f"{xml_parse:.3f}"]
        except Exception as exc:  # a shape FeatureIDE cannot express: reported, not timed
            xml_data, xml = None, [f"n/a ({type(exc).__name__})", "n/a"]
        row += [f"{fm_write:.3f}", f"{fm_parse:.3f}", f"{uvl_write:.3f}", f"{uvl_parse:.3f}"]
        row += xml
        verdict = "-"
        if args.flamapy_python:
            expected = [features, len(model.constraints)]
            seen = []
            with tempfile.TemporaryDirectory() as tmp:
                exports = {".uvl": uvl_text.encode(), ".xml": xml_data}
                for suffix, data in exports.items():
                    if data is None:
                        continue
                    target = Path(tmp) / f"{path.stem}{suffix}"
                    target.write_bytes(data)
                    out = subprocess.run(
                        [args.flamapy_python, "-c", FLAMAPY_READ, str(target)],
                        capture_output=True,
                        text=True,
                        check=False,
                    )
                    counts = json.loads(out.stdout) if out.returncode == 0 else None
                    seen.append(f"{suffix[1:]}: {'ok' if counts == expected else counts}")
                    failures += counts != expected
            verdict = ", ".join(seen)
        row.append(verdict)
        print("| " + " | ".join(row) + " |")
    print("\ntimes in seconds, best of", args.repeat)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
