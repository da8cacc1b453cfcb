"""The core runtime under the calls an HMI makes from several threads and from its
callbacks (issue 9, the project's reproducer scripts): one activity per core, every ending
call waits for the worker to be joined, re-entrant calls from the worker's own thread,
refused calls kept apart from the program's error, callbacks removed while in flight,
the file table's recycling and where a run starts.

Each test runs in a fresh subprocess (runtime_host.script): a defect may crash the
process or hang it, and is then reported as a failure with every thread's stack."""
import pytest

from compiler_host import SEED_PROGRAM
from runtime_host import run_script


@pytest.fixture
def run(run_python):
    return lambda body, seconds=10.0: run_script(run_python, body, seconds)


# ------------------------------------------------------------------ ending calls from two host threads

@pytest.mark.parametrize("second", ["destroy", "reset", "resetstatus"])
def test_second_ending_call_waits_until_the_worker_is_joined(run, second):
    # race_destroy.py: a host thread calls DestroyCNC while the worker sleeps in DriverGFunc;
    # a second thread's ending call must not return (nor free the program) before the worker
    # has left its callback and been joined.
    run(f"""
        SECOND = {second!r}
        load_ini(lib, 0)
        base = thread_count()      # before any worker (one that ended may still be exiting)
        assert compile_wait(lib, 0, lines_program(2000)) is None
        state = {{"left_callback": False}}
        inside = threading.Event()

        def slow_fifth(kind, part):
            if len(driver.parts) == 5:
                inside.set()
                time.sleep(0.3)            # a slow driver, once (the GIL released)
                state["left_callback"] = True

        driver = Driver(lib, 0, slow_fifth).install()
        start(lib, 0)
        assert inside.wait(10), "the simulation did not reach the fifth part"
        first = threading.Thread(target=lambda: lib.ToolChainCore_DestroyCNC(0))
        first.start()
        time.sleep(0.02)
        if SECOND == "destroy":
            rc = lib.ToolChainCore_DestroyCNC(0)
        elif SECOND == "reset":
            rc = lib.ToolChainCore_ResetCNC(0, 0, 0, None)
        else:
            rc = lib.ToolChainCore_ResetStatusCNC(0, 0)
        left, parts_at_return = state["left_callback"], len(driver.parts)
        # a call that ended nothing (ResetStatusCNC refused while the run ends) may return at once
        assert left or (SECOND == "resetstatus" and rc == -1), \
            f"the second call ({{SECOND}}, rc {{rc}}) returned while the worker was still in its callback"
        first.join()
        time.sleep(0.1)
        assert len(driver.parts) == parts_at_return, "a callback was called after the ending calls returned"
        assert lib.ToolChainCore_StatusCNC(0) == 0
        assert_threads_back(base)
        driver.remove()
        check_usable(lib, 0)
    """)


def test_resets_and_compilations_from_three_threads_never_run_two_workers(run):
    # race_compile.py: ResetCNC in a loop against two threads compiling in a loop on one
    # core. The library's threads are counted from inside the worker's status-text
    # callback and by the compiling threads: one worker, plus at most one that has been
    # joined and is leaving the kernel.
    run("""
        load_ini(lib, 0)
        code = lines_program(3000)
        stop = threading.Event()
        host_threads = 3
        seen = {"compiled": 0, "max_library_threads": 0, "resets_refused": 0}
        base = thread_count()

        def count():
            library_threads = thread_count() - base - host_threads
            seen["max_library_threads"] = max(seen["max_library_threads"], library_threads)

        text_cb = abi.SetStatusBarText(lambda user, pane, text, info: count() or 0)
        set_callback(lib, 0, abi.CB_SET_STATUS_BAR_TEXT, text_cb)

        def resetter():
            while not stop.is_set():
                if lib.ToolChainCore_ResetCNC(0, 0, 0, None) != 0:
                    seen["resets_refused"] += 1

        def compiler():
            while not stop.is_set():
                if lib.ToolChainCore_CompileFromMemory(0, b"r.nc", code) == 0:
                    seen["compiled"] += 1
                count()
                time.sleep(0.0001)

        threads = [threading.Thread(target=resetter)] + [threading.Thread(target=compiler) for _ in range(2)]
        for t in threads:
            t.start()
        time.sleep(1.5)
        stop.set()
        for t in threads:
            t.join()
        wait_status(lib, 0, lambda s: s != 1)
        set_callback(lib, 0, abi.CB_SET_STATUS_BAR_TEXT, None)
        assert seen["compiled"] > 0 and seen["resets_refused"] == 0, seen
        assert seen["max_library_threads"] <= 2, f"{seen['max_library_threads']} library threads at once"
        lib.ToolChainCore_DestroyCNC(0)
        assert_threads_back(base)
        check_usable(lib, 0)
    """, seconds=20)


def test_no_callback_after_destroy_returned(run):
    run("""
        load_ini(lib, 0)
        base = thread_count()      # before any worker (one that ended may still be exiting)
        assert compile_wait(lib, 0, lines_program(3000)) is None
        state = {"destroyed": False, "late": 0}

        def after_destroy(kind, part):
            if state["destroyed"]:
                state["late"] += 1

        driver = Driver(lib, 0, after_destroy).install()
        start(lib, 0)
        wait_status(lib, 0, lambda s: len(driver.parts) >= 100 or s != 10)
        assert lib.ToolChainCore_DestroyCNC(0) == 0
        state["destroyed"] = True
        time.sleep(0.2)
        assert state["late"] == 0, f"{state['late']} callbacks after DestroyCNC returned"
        assert lib.ToolChainCore_StatusCNC(0) == 0
        assert_threads_back(base)
    """)


# ------------------------------------------------------------------ calls from the worker's own thread

SQUARE_WITH_M = 'G1 X10 F1000\nG1 Y10\nM8\nG1 X0\nPRINT "half"\nG1 Y0\nM30\n'
MATH_WARNING_PROGRAM = ("G41 G1 X0 Y0 F1000\nG1 X10\nY10\nG1 X10\nG3 X2 Y0 I1 J0\nG1 X10\n"
                        "G40 G1 X0 Y-10\nM30\n")

# (callback number, its prototype in sf_tch.abi, program, G-code parameters, run regime or None)
REENTRY_SLOTS = {
    "DriverInitialize": ("CB_DRIVER_INITIALIZE", "DriverInitialize", SQUARE_WITH_M, {}, 10),
    "DriverGFunc": ("CB_DRIVER_G_FUNC", "DriverGFunc", SQUARE_WITH_M, {}, 10),
    "DriverGFunc-test": ("CB_DRIVER_G_FUNC", "DriverGFunc", SQUARE_WITH_M, {}, 20),
    "DriverMFunc": ("CB_DRIVER_M_FUNC", "DriverMFunc", SQUARE_WITH_M, {}, 10),
    "DriverEnd": ("CB_DRIVER_END", "DriverEnd", SQUARE_WITH_M, {}, 10),
    "AddOutputLog": ("CB_ADD_OUTPUT_LOG", "AddOutputLog", SQUARE_WITH_M, {}, 10),
    "SetStatusBarText": ("CB_SET_STATUS_BAR_TEXT", "SetStatusBarText", SQUARE_WITH_M, {}, None),
    "SetStatusBarProgress": ("CB_SET_STATUS_BAR_PROGRESS", "SetStatusBarProgress", SQUARE_WITH_M, {}, None),
    "DispAndLocateError": ("CB_DISP_AND_LOCATE_ERROR", "DispAndLocateError", "G1 X1\nQQ\n", {}, None),
    "MathWarning": ("CB_MATH_WARNING", "MathWarning", MATH_WARNING_PROGRAM,
                    {"absMode": 0, "correctionStrategy": 0x200000}, None),
}


@pytest.mark.parametrize("slot", REENTRY_SLOTS)
def test_destroy_from_a_callback_ends_the_activity(run, slot):
    # reentry.py destroy: the status stayed at 10 for ever and later compilations were refused.
    number, proto, code, params, regime = REENTRY_SLOTS[slot]
    run(f"""
        load_ini(lib, 0)
        set_params(lib, 0, **{params!r})
        if {slot!r} == "MathWarning":
            params = abi.GCODE_PARAMETERS()
            lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(params))
            params.correction[0].size = 2.0
            assert lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(params)) == 0
        fired = []

        def reenter(*args):
            if not fired:
                fired.append(lib.ToolChainCore_DestroyCNC(0))
            return 0

        callback = abi.{proto}(reenter)
        set_callback(lib, 0, abi.{number}, callback)
        base = thread_count()
        assert lib.ToolChainCore_CompileFromMemory(0, b"p.nc", {code!r}.encode()) == 0
        status = wait_status(lib, 0, lambda s: s != 1)
        if not fired:
            assert status == -1, f"compilation ended in status {{status}}"
            assert {regime!r} is not None, "the callback was not called during the compilation"
            start(lib, 0, {regime!r})
            status = wait_status(lib, 0, lambda s: s != {regime!r}, 5)
        assert fired == [0], f"DestroyCNC from the callback: {{fired}}"
        assert status == 0, f"status {{status}} after DestroyCNC from the callback"
        time.sleep(0.05)
        assert lib.ToolChainCore_StatusCNC(0) == 0
        assert_threads_back(base)
        set_callback(lib, 0, abi.{number}, None)
        set_params(lib, 0, absMode=1, correctionStrategy=0)
        check_usable(lib, 0)
    """)


@pytest.mark.parametrize("call, regime, expected", [
    ("DestroyCNC", 10, 0), ("DestroyCNC", 20, 0),
    ("ResetCNC", 10, -30), ("ResetCNC", 20, -30),
    ("StopCNCEx", 10, -11), ("StopCNCEx", 20, -21),
])
def test_ending_call_from_driver_gfunc_ends_the_run_after_the_callback(run, call, regime, expected):
    run(f"""
        load_ini(lib, 0)
        base = thread_count()      # before any worker (one that ended may still be exiting)
        assert compile_wait(lib, 0, SQUARE) is None
        calls = {{"DestroyCNC": lambda: lib.ToolChainCore_DestroyCNC(0),
                 "ResetCNC": lambda: lib.ToolChainCore_ResetCNC(0, 0, 0, None),
                 "StopCNCEx": lambda: lib.ToolChainCore_StopCNCEx(0, None)}}
        fired = []

        def on_second(kind, part):
            if len(driver.parts) == 2:
                fired.append(calls[{call!r}]())

        driver = Driver(lib, 0, on_second).install()
        start(lib, 0, {regime})
        status = wait_status(lib, 0, lambda s: s != {regime}, 5)
        assert fired == [0], fired
        assert status == {expected}, f"status {{status}} after {call} from DriverGFunc"
        time.sleep(0.05)
        assert len(driver.parts) == 2, f"parts delivered after {call} in the second: {{driver.parts}}"
        assert len(driver.threads) == 1
        assert_threads_back(base)
        driver.remove()
        check_usable(lib, 0)
    """)


@pytest.mark.parametrize("call", ["StartCNCEx", "CompileFromMemory", "CompileFromFile", "ResetStatusCNC"])
def test_starting_calls_from_a_callback_are_refused(run, call, tmp_path):
    program = tmp_path / "other.nc"
    program.write_bytes(b"G1 X5\n")
    run(f"""
        load_ini(lib, 0)
        base = thread_count()      # before any worker (one that ended may still be exiting)
        assert compile_wait(lib, 0, SQUARE) is None
        calls = {{"StartCNCEx": lambda: lib.ToolChainCore_StartCNCEx(0, 10, None),
                 "CompileFromMemory": lambda: lib.ToolChainCore_CompileFromMemory(0, b"x.nc", b"G1 X5\\n"),
                 "CompileFromFile": lambda: lib.ToolChainCore_CompileFromFile(0, {str(program).encode()!r}),
                 "ResetStatusCNC": lambda: lib.ToolChainCore_ResetStatusCNC(0, 0)}}
        refused = []

        def on_second(kind, part):
            if len(driver.parts) == 2:
                refused.append((calls[{call!r}](), last_call_error(lib, 0)))

        driver = Driver(lib, 0, on_second).install()
        start(lib, 0)
        status = wait_status(lib, 0, lambda s: s != 10, 5)
        (rc, error), = refused
        assert rc == -1, f"{call} from DriverGFunc -> {{rc}}"
        assert error is not None and "callback" in error[1].lower(), error
        assert "?" not in error[1], error
        assert status == -10, f"the run after the refused call ended in status {{status}}"
        assert len(driver.g_parts) == 4 and len(driver.threads) == 1, driver.parts
        assert last_error(lib, 0) is None, "the refused call replaced the program's error"
        assert_threads_back(base)
        driver.remove()
        check_usable(lib, 0)
    """)


def test_reset_and_restart_from_a_callback_never_start_a_second_worker(run):
    # reentry.py restart: a second worker ran beside the first (8 parts instead of 4).
    run("""
        load_ini(lib, 0)
        base = thread_count()      # before any worker (one that ended may still be exiting)
        assert compile_wait(lib, 0, SQUARE) is None
        results = []

        def on_second(kind, part):
            if len(driver.parts) == 2 and not results:
                results.append((lib.ToolChainCore_ResetCNC(0, 0, 0, None), lib.ToolChainCore_StartCNCEx(0, 10, None)))

        driver = Driver(lib, 0, on_second).install()
        start(lib, 0)
        status = wait_status(lib, 0, lambda s: s != 10, 5)
        time.sleep(0.1)
        assert results == [(0, -1)], results
        assert status == -30 and lib.ToolChainCore_StatusCNC(0) == -30
        assert len(driver.parts) == 2 and len(driver.threads) == 1, driver.parts
        assert_threads_back(base)
    """)


def test_restarts_from_callbacks_leave_no_thread(run):
    # reentry_leak.py: +958 MB of address space after 100 runs, one unjoined thread each.
    run("""
        load_ini(lib, 0)
        armed = [False]

        def restart_once(kind, part):
            if armed[0]:
                armed[0] = False
                lib.ToolChainCore_ResetCNC(0, 0, 0, None)
                lib.ToolChainCore_StartCNCEx(0, 10, None)

        driver = Driver(lib, 0, restart_once).install()

        def cycle():
            assert compile_wait(lib, 0, SQUARE) is None
            armed[0] = True
            start(lib, 0)
            wait_status(lib, 0, lambda s: s not in (1, 10), 5)
            time.sleep(0.001)
            assert lib.ToolChainCore_StatusCNC(0) not in (1, 10), "a second run started from the callback"

        base_threads = thread_count()
        for _ in range(5):        # the first workers' malloc arena and stack stay reserved
            cycle()
        base_vm = vm_size_kb()
        for _ in range(100):
            cycle()
        grown_mb = (vm_size_kb() - base_vm) / 1024
        assert_threads_back(base_threads, "before 105 runs")
        # a thread never joined keeps its 8 MB stack: two would show
        assert grown_mb < 16, f"address space grew by {grown_mb:.0f} MB in 100 runs"
    """, seconds=30)


# ------------------------------------------------------------------ errors of refused calls

def test_a_refused_call_does_not_replace_the_programs_error(run):
    run("""
        seen = []
        disp = abi.DispAndLocateError(lambda user, line, idx, text, info: seen.append(text.decode()) or 0)
        set_callback(lib, 0, abi.CB_DISP_AND_LOCATE_ERROR, disp)
        assert last_call_error(lib, 0) is None                   # never failed
        assert compile_wait(lib, 0, SQUARE) is None
        assert lib.ToolChainCore_StopCNCEx(0, None) == -1         # nothing runs
        refused = last_call_error(lib, 0)
        assert last_error(lib, 0) is None, f"GetLastError after a refused StopCNCEx: {last_error(lib, 0)}"
        assert refused is not None and "?" not in refused[1], refused
        assert seen and "?" not in seen[-1], seen               # the host saw it too
        assert lib.ToolChainCore_ResetCNC(0, 0, 0, None) == 0

        # a failed compilation keeps its error (number, line) through a refused call
        assert lib.ToolChainCore_CompileFromMemory(0, b"bad.nc", b"G1 X1\\nQQ\\n") == 0
        wait_status(lib, 0, lambda s: s != 1)
        program_error = last_error(lib, 0)
        assert program_error is not None and program_error[1] == 2
        assert lib.ToolChainCore_StartCNCEx(0, 10, None) == -1   # nothing compiled
        refused = last_call_error(lib, 0)
        assert last_error(lib, 0) == program_error
        assert refused is not None and "?" not in refused[1], refused
    """)


def test_an_error_text_a_thread_read_is_never_rewritten(run):
    # tsan_lastcallerror_text.py: GetLastCallError's texts were the core's one buffer,
    # rewritten by the next refused call on any thread while a host thread read it (torn
    # texts; a data race under ThreadSanitizer). Each kept error is published whole by a
    # pointer swap and stays as it was while the thread that read it holds it.
    run("""
        def text_pointer(info):
            return ctypes.c_void_p.from_buffer(info, abi.CALLBACK_INFO.m_fullError.offset).value

        info = abi.CALLBACK_INFO()
        assert lib.ToolChainCore_StopCNCEx(0, None) == -1                # nothing runs
        assert lib.ToolChainCore_GetLastCallError(0, ctypes.byref(info)) == 1
        held = text_pointer(info)
        text = ctypes.string_at(held)
        assert b"StopCNCEx" in text, text

        stop = threading.Event()
        def refuser():
            while not stop.is_set():
                lib.ToolChainCore_StopCNCEx(0, None)     # refused: a new error each time
                lib.ToolChainCore_ConfirmMFunc(0)        # refused: another text
        read = {"seen": 0, "torn": []}
        def reader():                                    # reads each new text at once
            mine = abi.CALLBACK_INFO()
            while not stop.is_set():
                if lib.ToolChainCore_GetLastCallError(0, ctypes.byref(mine)) == 1:
                    now = ctypes.string_at(text_pointer(mine))
                    read["seen"] += 1
                    if not (b"StopCNCEx" in now or b"M function" in now):
                        read["torn"].append(now)
        threads = [threading.Thread(target=refuser) for _ in range(2)] + [threading.Thread(target=reader)]
        for t in threads:
            t.start()
        deadline = time.monotonic() + 1.0
        while time.monotonic() < deadline:
            assert ctypes.string_at(held) == text        # what this thread holds stays
        stop.set()
        for t in threads:
            t.join()
        assert read["seen"] > 0 and not read["torn"], read["torn"][:3]
        # GetLastError: the same rule for the error of a compilation, which the next
        # compilation replaces while this thread holds the first one
        def compiled(text):
            assert lib.ToolChainCore_CompileFromMemory(0, b"bad.nc", text) == 0
            assert wait_status(lib, 0, lambda s: s != 1) == -1
        compiled(b"G1 X1\\nQQ\\n")
        assert lib.ToolChainCore_GetLastError(0, ctypes.byref(info)) == 1 and info.actLine == 2
        held, text = text_pointer(info), info.m_fullError
        compiled(b"G1 X1\\nG1 X2\\nQQ\\n")
        assert ctypes.string_at(held) == text
        assert lib.ToolChainCore_GetLastError(0, ctypes.byref(info)) == 1 and info.actLine == 3
    """)


# ------------------------------------------------------------------ callbacks removed while in flight

def test_removing_a_callback_waits_for_the_call_in_flight(run):
    # A host frees its function right after SetCallBack(NULL): here the ctypes thunk is
    # released, so a later call would jump to freed memory (180 calls seen on main).
    run("""
        load_ini(lib, 0)
        assert compile_wait(lib, 0, lines_program(3000)) is None
        state = {"inside": 0, "calls": 0}
        inside = threading.Event()

        def slow(user, part):
            state["inside"] += 1
            state["calls"] += 1
            inside.set()
            time.sleep(0.002)
            state["inside"] -= 1
            return 0

        callback = abi.DriverGFunc(slow)
        set_callback(lib, 0, abi.CB_DRIVER_G_FUNC, callback)
        start(lib, 0)
        assert inside.wait(10)
        assert lib.ToolChainCore_SetCallBack(0, abi.CB_DRIVER_G_FUNC, 0, None) == 0
        in_flight, calls = state["inside"], state["calls"]
        del callback
        import gc; gc.collect()
        time.sleep(0.1)
        assert in_flight == 0, "SetCallBack(NULL) returned while the callback was running"
        assert state["calls"] == calls, f"{state['calls'] - calls} calls after the callback was removed"
        lib.ToolChainCore_DestroyCNC(0)
    """)


def test_a_callback_removing_itself_does_not_deadlock(run):
    run("""
        load_ini(lib, 0)
        assert compile_wait(lib, 0, SQUARE) is None
        calls = []

        def remove_self(user, part):
            calls.append(part.contents.m_editorLine)
            if len(calls) == 2:
                assert lib.ToolChainCore_SetCallBack(0, abi.CB_DRIVER_G_FUNC, 0, None) == 0
            return 0

        callback = abi.DriverGFunc(remove_self)
        set_callback(lib, 0, abi.CB_DRIVER_G_FUNC, callback)
        start(lib, 0)
        assert wait_status(lib, 0, lambda s: s != 10, 5) == -10
        assert calls == [1, 2], calls
    """)


def test_callbacks_replacing_each_others_callback_never_deadlock(run):
    # setcallback_cross_deadlock.py: the DriverMFunc of two cores, inside at the same
    # time, each replace the other core's DriverMFunc. Waiting for the other's call to
    # return (as SetCallBack does outside callbacks) would wait for ever on both sides.
    run("""
        both_inside = threading.Barrier(2, timeout=5)
        returned = []

        def make(core):
            def driver_m(user, part):
                both_inside.wait()
                rc = lib.ToolChainCore_SetCallBack(1 - core, abi.CB_DRIVER_M_FUNC, 0,
                                                   ctypes.cast(thunks[1 - core], ctypes.c_void_p))
                returned.append((core, rc))
                return 0
            return abi.DriverMFunc(driver_m)

        thunks = [make(0), make(1)]
        for core in (0, 1):
            load_ini(lib, core)
            set_callback(lib, core, abi.CB_DRIVER_M_FUNC, thunks[core])
            assert compile_wait(lib, core, b"G1 X1 F6000\\nM7\\nG1 X2\\n") is None
        for core in (0, 1):
            start(lib, core)
        for core in (0, 1):
            assert wait_status(lib, core, lambda s: s != 10, 5) == -10
        assert sorted(returned) == [(0, 0), (1, 0)], returned
        assert lib.ToolChainCore_DestroyCNC(0) == 0 and lib.ToolChainCore_DestroyCNC(1) == 0
    """)


# ------------------------------------------------------------------ settings beside the machine

def test_set_look_ahead_beside_the_machines_starts(run):
    # tsan_setlookahead_race.py: SetLookAhead from a host thread while manual moves start
    # the machine's worker, which reads the look-ahead setting (a data race under
    # ThreadSanitizer until the worker copied it under the core's lock).
    run("""
        assert lib.ToolChainCore_SetTimeScale(0, 1e6) == 0
        stop = threading.Event()

        def host():
            k = 0
            while not stop.is_set():
                lib.ToolChainCore_SetLookAhead(0, k % 3)
                k += 1

        setter = threading.Thread(target=host)
        setter.start()
        for n in range(40):
            assert lib.ToolChainCore_GoToPosition(0, 2, (ctypes.c_double * 2)(n % 7, n % 5)) == 0
            assert wait_status(lib, 0, lambda s: s != 50) == -50
        stop.set()
        setter.join()
        assert lib.ToolChainCore_SetLookAhead(0, 0) == 0
    """)


# ------------------------------------------------------------------ file table

def test_file_names_are_recycled_and_keep_their_run_time(run):
    run("""
        load_ini(lib, 0)
        set_params(lib, 0, calcTime=1)
        for n in range(200):
            name = b"part%03d.nc" % n
            assert compile_wait(lib, 0, b"G1 X%d Y5 F1000\\nG1 X0 Y0\\n" % (n + 1), name) is None
            status, driver = simulate(lib, 0)
            assert status == -10
            index = driver.parts[0][2]
            assert index >= 0, f"program {n} ({name}) got file index {index}"
            assert lib.ToolChainCore_FileToIdx(0, name) == index
            assert lib.ToolChainCore_IdxToFile(0, index) == name
            assert lib.ToolChainCore_GetGCodeRunTime(0, index) > 0, f"no run time stored for {name}"
    """, seconds=30)


# ------------------------------------------------------------------ where a run starts

SEED_RELATIVE = SEED_PROGRAM       # the interpolator manual's example: relative coordinates (absMode 0)


def test_a_simulation_never_moves_the_machine(run):
    # The manual's relative example compiled and simulated three times ended at (47.25, 63.13),
    # (94.50, 126.26), (141.75, 189.39): each dry run moved the next one's start.
    run(f"""
        load_ini(lib, 0)
        set_params(lib, 0, absMode=0)
        reset_to(lib, 0, 0.0, 0.0, 0.0)
        ends = []
        for regime in (10, 20, 10):
            assert compile_wait(lib, 0, {SEED_RELATIVE!r}.encode(), b"seed003.nc") is None
            status, driver = simulate(lib, 0, regime)
            assert status == -regime
            g = driver.g_parts
            assert g[0][3][:2] == (0.0, 0.0), f"run {{len(ends)}} starts at {{g[0][3]}}"
            ends.append(g[-1][4])
        assert ends[0] == ends[1] == ends[2], ends
        # relative throughout: the end is the sum of the moves
        words = [dict((w[0], float(w[1:])) for w in line.split() if w[0] in "XY")
                 for line in {SEED_RELATIVE!r}.splitlines()]
        assert abs(ends[0][0] - sum(w.get("X", 0) for w in words)) < 1e-6, ends[0]
        assert abs(ends[0][1] - sum(w.get("Y", 0) for w in words)) < 1e-6, ends[0]

        # DestroyCNC keeps the machine position
        reset_to(lib, 0, 50.0, 60.0, -5.0)
        assert lib.ToolChainCore_DestroyCNC(0) == 0
        assert compile_wait(lib, 0, b"G91 G1 X1 Y2 F1000\\n") is None
        status, driver = simulate(lib, 0)
        assert status == -10
        assert driver.g_parts[0][3] == (50.0, 60.0, -5.0), driver.g_parts
        assert driver.g_parts[0][4] == (51.0, 62.0, -5.0), driver.g_parts
    """)


def test_axes_a_program_does_not_name_start_where_the_machine_is_at_the_run(run):
    run("""
        load_ini(lib, 0)
        reset_to(lib, 0, 50.0, 60.0, -5.0)
        assert compile_wait(lib, 0, b"G0 X10\\n") is None
        reset_to(lib, 0, 0.0, 0.0, 50.0)
        status, driver = simulate(lib, 0)
        assert status == -10
        first = driver.g_parts[0]
        assert first[3] == (0.0, 0.0, 50.0) and first[4] == (10.0, 0.0, 50.0), first
    """)
