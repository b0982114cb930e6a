#!/usr/bin/python3
# Reads a Prometheus text exposition (format 0.0.4) on stdin, parses it with the Prometheus project's
# own Python client (Debian's python3-prometheus-client, an independent reader), checks the rules
# that parser does not enforce, and prints every family as JSON:
#   {"family": {"type": "counter", "samples": [[sample name, {labels}, value], ...]}, ...}
# Exit status 1 with the broken rule on stderr.
import json
import math
import re
import sys

from prometheus_client.parser import text_string_to_metric_families


def fail(message):
    print("metrics_check: " + message, file=sys.stderr)
    sys.exit(1)


text = sys.stdin.read()
if not text.endswith("\n"):
    fail("the exposition does not end with a newline")

# Each family's HELP and TYPE once, before its samples; its samples together.
typed, helped, finished, current = {}, set(), set(), None
for line in text.split("\n")[:-1]:
    if line.startswith("# HELP "):
        helped.add(line.split(" ")[2])
    elif line.startswith("# TYPE "):
        _, _, name, kind = line.split(" ")
        if name in typed:
            fail("TYPE of %s given twice" % name)
        if name not in helped:
            fail("TYPE of %s before its HELP" % name)
        typed[name] = kind
    elif line and not line.startswith("#"):
        sample = re.match(r"[a-zA-Z_:][a-zA-Z0-9_:]*", line).group(0)
        family = next((f for f in typed if sample == f or
                       (re.fullmatch(re.escape(f) + r"_(bucket|sum|count)", sample) and typed[f] == "histogram")), None)
        if family is None:
            fail("sample %s has no TYPE before it" % sample)
        if family != current:
            if family in finished:
                fail("the samples of %s are not together" % family)
            if current:
                finished.add(current)
            current = family
        if typed[family] == "counter" and not sample.endswith("_total"):
            fail("counter sample %s does not end in _total" % sample)

out = {}
for family in text_string_to_metric_families(text):
    samples = [[s.name, s.labels, s.value] for s in family.samples]
    if family.type == "histogram":
        series = {}
        for name, labels, value in samples:
            key = tuple(sorted((k, v) for k, v in labels.items() if k != "le"))
            series.setdefault(key, {"buckets": [], "count": None, "sum": None})
            if name.endswith("_bucket"):
                series[key]["buckets"].append((float(labels["le"]), value))
            elif name.endswith("_count"):
                series[key]["count"] = value
            elif name.endswith("_sum"):
                series[key]["sum"] = value
        for key, s in series.items():
            bounds = [b for b, _ in s["buckets"]]
            counts = [c for _, c in s["buckets"]]
            if bounds != sorted(bounds) or not bounds or not math.isinf(bounds[-1]):
                fail("%s %s: buckets not in increasing order ending at +Inf" % (family.name, key))
            if counts != sorted(counts):
                fail("%s %s: bucket counts are not cumulative" % (family.name, key))
            if s["count"] is None or s["sum"] is None or counts[-1] != s["count"]:
                fail("%s %s: the +Inf bucket differs from _count, or _sum is missing" % (family.name, key))
    out[family.name] = {"type": family.type, "samples": samples}
print(json.dumps(out))
