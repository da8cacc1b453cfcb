"""Draws the bundled sample program into docs/sample.png (the README's picture):

    python docs/make_sample_picture.py [OUT]

The same as ``sf-tch plot <sample> --radius 1 -o docs/sample.png``, at a size that
reads well on a README page."""
import sys
from pathlib import Path

import sf_tch
from sf_tch.plot import save_plot


def main() -> int:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent / "sample.png"
    with sf_tch.compile(sf_tch.sample_program(), radius=1.0, start=(0.0, 0.0, 0.0)) as program:
        program.check()
        save_plot(program, str(out), dpi=100)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
