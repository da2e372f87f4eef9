"""Screenshots of the Snakemake report as a reader sees it, in headless Chromium (issue 20).

Usage: ``python benchmarks/report_screenshots.py results/report.html -o /tmp/report-shots [--width 1400]``

The report is one page whose views are chosen by clicking; for each result (the summary, the tables' HTML pages,
every figure) this writes a copy of the report that opens that result with its caption panel (the report's own
``app.setView``, as its buttons call it) and screenshots it. Prints one line per PNG with its size; look at them.
"""

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

RESULTS = (
    "summary.html",
    "table1.html",
    "table2.html",
    "claims.html",
    "figure4.html",
    "generalisation.html",
    "camera_rigs.html",
    "robustness.html",
    "figure4.png",
    "gallery.png",
    "joint_errors.png",
    "error_over_time.png",
    "generalisation.png",
    "camera_rigs.png",
    "robustness.png",
)

_OPEN = """<script>
window.addEventListener("load", () => setTimeout(() => {
  const path = Object.keys(results).find((k) => k.endsWith("/" + NAME));
  if (path === undefined) { document.title = "missing"; return; }
  const html = path.endsWith(".html");
  app.setView({navbarMode: "resultinfo", content: html ? "html" : "img", contentPath: results[path].data_uri,
               resultPath: path});
}, 300));
</script>"""


def chromium() -> str:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return name
    sys.exit("report_screenshots: no chromium on PATH (apt-get install -y chromium)")


def shoot(page: Path, png: Path, width: int, height: int) -> None:
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run(
            [
                chromium(),
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-background-networking",
                "--no-first-run",
                f"--user-data-dir={profile}",
                "--hide-scrollbars",
                "--virtual-time-budget=8000",
                f"--window-size={width},{height}",
                f"--screenshot={png}",
                page.resolve().as_uri(),
            ],
            check=True,
            capture_output=True,
            timeout=180,
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("report", type=Path)
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--width", type=int, default=1400)
    parser.add_argument("--height", type=int, default=2000)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    text = args.report.read_text()
    shoot(args.report, args.out / "00_report.png", args.width, args.height)
    print(args.out / "00_report.png", (args.out / "00_report.png").stat().st_size, "bytes")
    for i, name in enumerate(RESULTS, 1):
        script = _OPEN.replace("NAME", json.dumps(name))
        page = args.out / f"open_{name}.html"
        at = text.rindex("</body>")  # the last one: the report's scripts hold the string too
        page.write_text(text[:at] + script + text[at:])
        png = args.out / f"{i:02d}_{name.replace('.', '_')}.png"
        shoot(page, png, args.width, args.height)
        page.unlink()
        print(png, png.stat().st_size, "bytes")


if __name__ == "__main__":
    main()
