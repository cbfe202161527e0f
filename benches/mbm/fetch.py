"""Fetches the vamp-planner sdist (MotionBenchMaker problems) from PyPI into a directory.

Usage: fetch.py DIR

Downloads the pinned release's sdist through PyPI's JSON API (no build step, unlike
`pip download --no-binary`) and checks its SHA-256 against PyPI's digest and the pin below.
"""

import hashlib
import json
import os
import sys
import urllib.request

VERSION = "0.6.4"
SHA256 = "d3150c6b67ff941af9ad56480b31d3fb73b12211ea21dc684f7737b059f6daba"


def main() -> None:
    out = sys.argv[1]
    meta = json.load(urllib.request.urlopen("https://pypi.org/pypi/vamp-planner/json", timeout=60))
    files = meta["releases"].get(VERSION) or []
    sdist = next((u for u in files if u["packagetype"] == "sdist"), None)
    if sdist is None:
        sys.exit(f"vamp-planner {VERSION}: PyPI lists no sdist")
    if sdist["digests"]["sha256"] != SHA256:
        sys.exit(f"vamp-planner {VERSION}: PyPI's digest differs from the pinned one")
    data = urllib.request.urlopen(sdist["url"], timeout=600).read()
    if hashlib.sha256(data).hexdigest() != SHA256:
        sys.exit(f"vamp-planner {VERSION}: the download does not match its digest")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, sdist["filename"]), "wb") as f:
        f.write(data)


if __name__ == "__main__":
    main()
