"""python -m abi_check [--header PATH] [--library PATH] [--diff-only]"""
import argparse
import sys

from . import check, default_header, format_report


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m abi_check",
                                     description="Compare tgm_cnc.h, the ctypes mirror sf_tch.abi, "
                                                 "libSF_TCh.so and the sizes of ABI.md.")
    parser.add_argument("--header", help="C header (default: the installed sf_tch/include/tgm_cnc.h, "
                                         "else include/tgm_cnc.h of the source tree)")
    parser.add_argument("--library", help="shared library (default: sf_tch.library_path())")
    parser.add_argument("--diff-only", action="store_true", help="print only differences and the summary")
    args = parser.parse_args(argv)
    report = check(args.header or default_header(), args.library)
    print(format_report(report, args.diff_only))
    return 1 if report.differences else 0


if __name__ == "__main__":
    sys.exit(main())
