"""How HMIs load the library: plain ctypes.CDLL without sf_tch, and two handles of the
same path (sf_tch.library.load() and the host's own CDLL) sharing one state."""


def test_plain_ctypes_without_sf_tch(run_python, lib_path):
    out = run_python(f"""
        import ctypes, sys, time
        lib = ctypes.CDLL({lib_path!r})
        u32, i32 = ctypes.c_uint32, ctypes.c_int32

        lib.ToolChainCore_StatusCNC.argtypes = (u32,)
        print(lib.ToolChainCore_StatusCNC(0), lib.ToolChainCore_StatusCNC(3))

        lib.ToolChainCore_GetStructuresSize.argtypes = (u32, u32, ctypes.POINTER(u32))
        items = (u32 * 9)()
        print(lib.ToolChainCore_GetStructuresSize(0, 9, items), list(items))

        # GCODE_PARAMETERS as raw bytes: absMode at 0, startAngle at 408
        lib.ToolChainCore_GetGCodeParameters.argtypes = (u32, ctypes.c_void_p)
        lib.ToolChainCore_SetGCodeParameters.argtypes = (u32, ctypes.c_void_p)
        buf = ctypes.create_string_buffer(1112)
        print(lib.ToolChainCore_GetGCodeParameters(0, buf))
        absmode = i32.from_buffer(buf, 0)
        angle = ctypes.c_double.from_buffer(buf, 408)
        print(absmode.value, angle.value)
        absmode.value, angle.value = 0, 45.0
        print(lib.ToolChainCore_SetGCodeParameters(0, buf))
        back = ctypes.create_string_buffer(1112)
        lib.ToolChainCore_GetGCodeParameters(0, back)
        print(back.raw == buf.raw, i32.from_buffer(back, 0).value, ctypes.c_double.from_buffer(back, 408).value)

        # compile an empty program: 0 at once, status already 1 or -1, then -1
        lib.ToolChainCore_CompileFromMemory.argtypes = (u32, ctypes.c_char_p, ctypes.c_char_p)
        rc = lib.ToolChainCore_CompileFromMemory(0, b"empty.nc", b"")
        first = lib.ToolChainCore_StatusCNC(0)
        deadline = time.time() + 10
        while lib.ToolChainCore_StatusCNC(0) == 1 and time.time() < deadline:
            time.sleep(0.005)
        print(rc, first in (1, -1), lib.ToolChainCore_StatusCNC(0))

        lib.ToolChainCore_GetVersionString.restype = ctypes.c_char_p
        lib.ToolChainCore_GetVersionString.argtypes = (u32,)
        print(bool(lib.ToolChainCore_GetVersionString(0)))
        lib.ToolChainCore_DestroyCNC.argtypes = (u32,)
        print(lib.ToolChainCore_DestroyCNC(0), lib.ToolChainCore_StatusCNC(0))
        print(any(name == "sf_tch" or name.startswith("sf_tch.") for name in sys.modules))
    """, cwd="/").stdout.splitlines()
    assert out == [
        "0 -1234",
        "0 [8, 1112, 616, 112, 32, 1280, 52, 448, 32]",
        "0",
        "1 360.0",
        "0",
        "True 0 45.0",
        "0 True -1",
        "True",
        "0 0",
        "False",
    ]


def test_two_handles_share_one_state(run_python, lib_path):
    out = run_python(f"""
        import ctypes
        from sf_tch import abi, library, library_path
        mine = library.load()
        assert library_path() == {lib_path!r}
        host = ctypes.CDLL({lib_path!r})            # the HMI's own handle, untyped
        print(host._handle == mine._handle)

        p = abi.GCODE_PARAMETERS()
        mine.ToolChainCore_GetGCodeParameters(1, ctypes.byref(p))
        p.startAngle, p.tolerance[0], p.M30_programEnd2 = 12.5, 0.0125, 31
        print(mine.ToolChainCore_SetGCodeParameters(1, ctypes.byref(p)))
        q = abi.GCODE_PARAMETERS()
        print(host.ToolChainCore_GetGCodeParameters(1, ctypes.byref(q)), q.startAngle, q.tolerance[0], q.M30_programEnd2)

        host.ToolChainCore_FileToIdx.argtypes = (ctypes.c_uint32, ctypes.c_char_p)
        idx = host.ToolChainCore_FileToIdx(2, b"shared.nc")
        print(idx, mine.ToolChainCore_IdxToFile(2, idx), mine.ToolChainCore_FileToIdx(2, b"shared.nc"))

        host.ToolChainCore_SetLogValue(0x23)
        print(hex(mine.ToolChainCore_GetLogValue()))
    """).stdout.splitlines()
    assert out == ["True", "0", "0 12.5 0.0125 31", "0 b'shared.nc' 0", "0x23"]
