"""python -m sf_tch.abi_check (python -m abi_check in a source checkout)
[--header PATH] [--library PATH] [--diff-only]"""
from __future__ import annotations

import argparse
import sys

from . import NO_COMPILER, check, default_header, find_compiler, format_report


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog=f"python -m {__package__}",
                                     description="Compare tgm_cnc.h, the ctypes mirror sf_tch.abi, "
                                                 "libSF_TCh.so and the sizes of the vendor's structures.")
    parser.add_argument("--header", help="C header (default: the installed sf_tch/include/tgm_cnc.h, "
                                         "else include/tgm_cnc.h of the source tree)")
    parser.add_argument("--library", help="shared library (default: sf_tch.library_path())")
    parser.add_argument("--diff-only", action="store_true", help="print only differences and the summary")
    args = parser.parse_args(argv)
    if find_compiler() is None:
        # first, before the table: the reason every layout below is unmeasured
        print(f"{__package__}: {NO_COMPILER}; install one (e.g. gcc) or set CC", flush=True)
    report = check(args.header or default_header(), args.library)
    print(format_report(report, args.diff_only))
    return 1 if report.differences else 0


if __name__ == "__main__":
    sys.exit(main())
