"""Compile errors: the number, the line and the file a host is told, on every channel
(docs/api.md, docs/structures.md, docs/errors.md)."""
import ctypes
import math

from .. import abi
from .checks import Differs, check, expect, near
from .dialect import SEED_PROGRAM
from .host import Recorder

A, S, E = "api.md", "structures.md", "errors.md"


def _error(host, code, name="err.nc"):
    err = host.compile(code, name=name)
    if err is None:
        raise Differs("a compile error", None, "GetLastError")
    return err


def _line_check(name, code, line, what):
    @check("errors", f"line_{name}", S, "CALLBACK_INFO — errors and progress",
           f"GetLastError's actLine is the 1-based line in error ({what}, line {line}), fileIdx its file")
    def _(host):
        number, got_line, fidx, text, _ = _error(host, code, "lines.nc")
        expect(line, got_line, "actLine")
        expect("lines.nc", host.texts.back(host.lib.ToolChainCore_IdxToFile(0, fidx)), "IdxToFile(fileIdx)")


_line_check("division", "G1 X10 F1000\nG1 X1/0\n", 2, "a division by zero")
_line_check("arc_without_centre", "G1 X1 F1000\n\n(comment)\nG2 X10 Y0\n", 4, "an arc without a centre")
_line_check("unknown_g", "%\nG1 X1 F100\nG1 Y1\nG1234 X2\n", 4, "an unknown G function")
_line_check("unknown_function", "G1 X1 F100\nG1 X FOO(2)\nG1 Y1\n", 2, "an unknown function")
_line_check("undefined_label", "G1 X1 F100\nG1 Y2\nCALL nowhere\n", 3, "a call of an undefined label")


@check("errors", "seed_absolute_400", S, "CALLBACK_INFO — errors and progress",
       "the interpolator manual's example compiled with absMode 1 fails on line 4 with error 400, "
       "the wrongly entered arc centre (the structures description's example error)")
def _(host):
    host.set_params(0, absMode=1)
    number, line, _, text, _ = _error(host, SEED_PROGRAM)
    expect((400, 4), (number, line), "(stringId, actLine)")
    if not text.startswith("Wrongly entered centre of circular interpolation XY\nStart X = "):
        raise Differs("Wrongly entered centre of circular interpolation XY\\nStart X = …", text[:60], "m_fullError")


@check("errors", "seed_absolute_400_arguments", S, "CALLBACK_INFO — errors and progress",
       "error 400's arguments are exactly its format's six: the start and end of the arc, the chord and "
       "twice the radius, one per line (a panel formats its own text with them)")
def _(host):
    host.set_params(0, absMode=1)
    *_, args = _error(host, SEED_PROGRAM)
    want = [60.6051, 40.7723, 0.0, -2.5202, math.hypot(60.6051, 40.7723 + 2.5202), 2 * math.hypot(3.0336, 1.2601)]
    try:
        got = [float(a) for a in args.split("\n")]
    except ValueError:
        raise Differs(want, args.split("\n"), "m_errorArguments") from None
    if len(got) != 6:
        raise Differs(want, args.split("\n"), "m_errorArguments")
    for w, g in zip(want, got):
        near(w, g, 1e-4, "m_errorArguments")


@check("errors", "file_named", A, "Compilation",
       "an error in a file compiled by CompileFromFile names that file (IdxToFile of fileIdx)")
def _(host):
    path = host.file("bad file.nc", "G1 X1 F100\nG1 X1/0\n")
    expect(0, host.lib.ToolChainCore_CompileFromFile(0, host.texts.arg(path)), "CompileFromFile")
    host.wait(0, lambda s: s != 1)
    err = host.last_error(0)
    if err is None:
        raise Differs("an error", None, "GetLastError")
    expect(2, err[1], "actLine")
    expect(path, host.texts.back(host.lib.ToolChainCore_IdxToFile(0, err[2])), "IdxToFile(fileIdx)")


@check("errors", "disp_and_locate", A, "Callbacks",
       "every error goes at once to DispAndLocateError with its line and file index, the same as GetLastError")
def _(host):
    rec = Recorder(host, 0, driver=False)
    number, line, fidx, _, _ = _error(host, "G1 X1 F100\nG1 Y1\nG1 X1/0\n")
    errors = rec.of("error")
    if not errors:
        raise Differs("a DispAndLocateError call", rec.kinds(), "callbacks")
    expect((line, fidx), errors[-1][:2], "(editorLine, fileIdx)")


@check("errors", "output_log_tab0", A, "Callbacks", "every error also goes to AddOutputLog on tab 0")
def _(host):
    rec = Recorder(host, 0, driver=False)
    _error(host, "G1 X1/0\n")
    if not any(tab == 0 for tab, _ in rec.of("log")):
        raise Differs("an AddOutputLog call on tab 0", rec.of("log"), "AddOutputLog")


@check("errors", "single_core_names", A, "Compilation",
       "ToolChain_GetLastError is core 0's GetLastError")
def _(host):
    number, line, *_ = _error(host, "G1 X1 F100\nG1 X1/0\n")
    info = abi.CALLBACK_INFO()
    expect(1, host.lib.ToolChain_GetLastError(ctypes.byref(info)), "ToolChain_GetLastError")
    expect((number, line), (info.stringId, info.actLine), "(stringId, actLine)")


@check("errors", "cores_apart", A, "Conventions",
       "each core keeps its own error: an error on core 1 leaves core 0's GetLastError as it was")
def _(host):
    host.compiled("G1 X1 F100\n", core=0)
    err = host.compile("G1 X1/0\n", core=1)
    if err is None:
        raise Differs("an error on core 1", None, "GetLastError(1)")
    expect(None, host.last_error(0), "GetLastError(0)")


@check("errors", "prefix_named", A, "Parameters",
       "an error in the G-code prefix names the file __prefix__")
def _(host):
    expect(0, host.lib.ToolChainCore_GCodePrefixPostfix(0, b"G1 X1/0\n", None), "GCodePrefixPostfix")
    err = _error(host, "G1 X1 F100\n")
    expect("__prefix__", host.texts.back(host.lib.ToolChainCore_IdxToFile(0, err[2])), "IdxToFile(fileIdx)")


@check("errors", "error_cleared", A, "Compilation",
       "a good compilation after a failed one: GetLastError returns 0 again")
def _(host):
    _error(host, "G1 X1/0\n")
    host.compiled("G1 X1 F100\n")
