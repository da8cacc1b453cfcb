// Panel.cs -- a small .NET panel on the binding SfTch.cs: start-up check of the structures,
// a compilation, an error, a simulation with callbacks, a run of the offline machine with
// GetPos polled while the callbacks arrive, and DestroyCNC. Prints a report (one fact a
// line) that tests/test_dotnet.py compares with the Python package's results.
//
//   mcs -out:panel.exe SfTch.cs Panel.cs        (Mono; or a .NET project with both files)
//   mono panel.exe                              (in a folder with SF_TCh.ini and demo.nc,
//                                                libSF_TCh.so beside it or on LD_LIBRARY_PATH)
using System;
using System.Globalization;
using System.Threading;
using SfTch;

static class Panel
{
    static string N(double v) { return v.ToString("R", CultureInfo.InvariantCulture); }

    static void WaitIdle(uint core)
    {
        DateTime until = DateTime.UtcNow.AddSeconds(300);
        while (Native.ToolChainCore_IsBusy(core) > 0)
        {
            if (DateTime.UtcNow > until) throw new TimeoutException("core " + core + " did not end");
            Thread.Sleep(1);
        }
    }

    static void Load(uint core, double radius)
    {
        uint cores;
        using (var ini = HostText.Of("SF_TCh.ini"))
            Console.WriteLine("load: " + Native.ToolChainCore_LoadFromIni(core, ini.Pointer, out cores) + ", cores " + cores);
        var p = new GCODE_PARAMETERS();
        Native.ToolChainCore_GetGCodeParameters(core, ref p);
        for (int k = 0; k < 8; k++) p.correction[k].size = radius;
        p.calcTime = 1;
        Console.WriteLine("parameters: " + Native.ToolChainCore_SetGCodeParameters(core, ref p));
    }

    static int Compile(uint core, string file)
    {
        int rc;
        using (var name = HostText.Of(file)) rc = Native.ToolChainCore_CompileFromFile(core, name.Pointer);
        WaitIdle(core);
        return rc;
    }

    static void PrintError(uint core)
    {
        CALLBACK_INFO info;
        if (Native.ToolChainCore_GetLastError(core, out info) != 1) { Console.WriteLine("error: none"); return; }
        Console.WriteLine("error: " + info.stringId + " line " + info.actLine + " file " +
                          Texts.Host(Native.ToolChainCore_IdxToFile(core, info.fileIdx)) + ": " + info.FullError);
        Console.WriteLine("error arguments: " + string.Join(" | ", info.Arguments));
    }

    // what the callbacks of a run saw (library threads write, the panel reads after the run)
    static long gCalls, mCalls, inits, ends, progress, errorCalls, warnings, outputs;
    static double cut, rapid;
    static string errorText = "";

    static void SetCallbacks(uint core, bool on, bool throwingM)
    {
        Callbacks.Set(core, Tc.CB_ADD_OUTPUT_LOG, on ? Callbacks.OutputLog((tab, text, info) => Interlocked.Increment(ref outputs)) : null);
        Callbacks.Set(core, Tc.CB_DISP_AND_LOCATE_ERROR, on ? Callbacks.Error((line, file, text, info) =>
        {
            Interlocked.Increment(ref errorCalls);
            errorText = "line " + line + ": " + text + " (error " + info.stringId + ")";
        }) : null);
        Callbacks.Set(core, Tc.CB_SET_STATUS_BAR_PROGRESS, on ? Callbacks.Progress(percent => Interlocked.Increment(ref progress)) : null);
        Callbacks.Set(core, Tc.CB_MATH_WARNING, on ? Callbacks.Warning(info => Interlocked.Increment(ref warnings)) : null);
        Callbacks.Set(core, Tc.CB_DRIVER_INITIALIZE, on ? Callbacks.Initialize((n, mode) => { Interlocked.Increment(ref inits); return 0; }) : null);
        Callbacks.Set(core, Tc.CB_DRIVER_G_FUNC, on ? Callbacks.Part(part =>
        {
            // the simulation hands each part's length in the N address
            if (part.m_func != 0) cut += part.m_pars.N; else rapid += part.m_pars.N;
            Interlocked.Increment(ref gCalls);
            return 0;
        }) : null);
        Callbacks.Set(core, Tc.CB_DRIVER_M_FUNC, on ? Callbacks.Part(part =>
        {
            Interlocked.Increment(ref mCalls);
            if (throwingM) throw new InvalidOperationException("a panel's bug in DriverMFunc");
            return 0;
        }) : null);
        Callbacks.Set(core, Tc.CB_DRIVER_END, on ? Callbacks.End(() => Interlocked.Increment(ref ends)) : null);
    }

    static void ResetCounts()
    {
        gCalls = mCalls = inits = ends = progress = errorCalls = warnings = outputs = 0;
        cut = rapid = 0;
    }

    static int Main()
    {
        // the start-up check: a structure declared too small would be written past its end
        uint[] sizes = Layout.Check();
        Console.WriteLine("structure sizes: " + string.Join(" ", Array.ConvertAll(sizes, s => s.ToString())) + ", checked");
        Console.WriteLine("pointer size: " + IntPtr.Size);
        string version = Texts.Host(Native.ToolChainCore_GetVersionString(0));
        Console.WriteLine("version: " + version.Substring(0, version.IndexOf('(') < 0 ? version.Length : version.IndexOf('(')).Trim());

        Console.WriteLine("== compile");
        Load(0, 1.0);
        Console.WriteLine("compile: " + Compile(0, "demo.nc") + ", status " + Native.ToolChainCore_StatusCNC(0));
        var box = new GCODE_INFO();
        box.m_size = new GCODE_SIZE[4];
        Native.ToolChainCore_GetGCodeSizeInfo(0, ref box);
        Console.WriteLine("box: X " + N(box.m_size[0].m_minimalPos.x) + ".." + N(box.m_size[0].m_maximalPos.x) +
                          " Y " + N(box.m_size[0].m_minimalPos.y) + ".." + N(box.m_size[0].m_maximalPos.y));

        Console.WriteLine("== error");
        ResetCounts();
        SetCallbacks(0, true, false);
        int rc;
        using (var name = HostText.Of("chyba_řádek.nc"))
        using (var code = HostText.Narrow("G90\nG1 X10 Y5 F500\nG999 X5\nM2\n"))
            rc = Native.ToolChainCore_CompileFromMemory(0, name.Pointer, code.Pointer);
        WaitIdle(0);
        Console.WriteLine("compile: " + rc + ", status " + Native.ToolChainCore_StatusCNC(0));
        PrintError(0);
        Console.WriteLine("DispAndLocateError: " + errorCalls + ", " + errorText);

        Console.WriteLine("== simulation with callbacks");
        Compile(0, "demo.nc");
        ResetCounts();
        Native.ToolChainCore_ResetCNC(0, Tc.RESET_MARK_START_ONLY, 0, null);
        Console.WriteLine("simulation: " + Native.ToolChainCore_StartCNCEx(0, Tc.RUN_SIMULATION, IntPtr.Zero));
        GC.Collect();                     // the delegates are kept: the library may call them now
        GC.WaitForPendingFinalizers();
        WaitIdle(0);
        Console.WriteLine("status: " + Native.ToolChainCore_StatusCNC(0));
        Console.WriteLine("motion parts: " + gCalls + ", cut " + N(cut) + " mm, rapid " + N(rapid) + " mm, M " + mCalls);
        Console.WriteLine("initialize " + inits + ", end " + ends + ", progress reports: " + (progress > 0 ? "yes" : "no"));
        PrintError(0);

        Console.WriteLine("== a callback that throws");
        ResetCounts();
        SetCallbacks(0, true, true);
        Native.ToolChainCore_ResetCNC(0, Tc.RESET_MARK_START_ONLY, 0, null);
        Native.ToolChainCore_StartCNCEx(0, Tc.RUN_SIMULATION, IntPtr.Zero);
        WaitIdle(0);
        Console.WriteLine("status: " + Native.ToolChainCore_StatusCNC(0) + ", M " + mCalls + ", caught: " + Callbacks.Faults +
                          " (" + (Callbacks.FirstFault == null ? "none" : Callbacks.FirstFault.Message) + ")");

        Console.WriteLine("== offline machine, GetPos polled");
        SetCallbacks(0, true, false);
        ResetCounts();
        Native.ToolChainCore_SetTimeScale(0, 50.0);
        Native.ToolChainCore_ResetCNC(0, Tc.RESET_MARK_START_ONLY, 0, null);
        Console.WriteLine("start: " + Native.ToolChainCore_StartCNCEx(0, Tc.RUN_FORWARD, IntPtr.Zero));
        long polls = 0, failed = 0, wentBack = 0, seenDuring = 0;
        double last = 0;
        SIMPLE_GM_PARAMS pos;
        GM_PARAMS_ENHANCED enh;
        DateTime until = DateTime.UtcNow.AddSeconds(300);
        while (Native.ToolChainCore_StatusCNC(0) > 0 && DateTime.UtcNow < until)
        {
            if (Native.ToolChainCore_GetPos(0, 0, out pos, out enh) != 0 || enh.m_statusCNC == Tc.STATUS_INVALID) { failed++; continue; }
            if (enh.m_actPartsLen + 1e-9 < last) wentBack++;
            last = enh.m_actPartsLen;
            polls++;
            if (Interlocked.Read(ref gCalls) > 0 && enh.m_statusCNC > 0) seenDuring = 1;
            if (polls % 100 == 0) GC.Collect();
        }
        WaitIdle(0);
        Native.ToolChainCore_GetPos(0, 0, out pos, out enh);
        Console.WriteLine("status: " + Native.ToolChainCore_StatusCNC(0));
        Console.WriteLine("polls: " + (polls > 0 ? "yes" : "no") + ", failed " + failed + ", went back " + wentBack +
                          ", callbacks during the polls: " + (seenDuring > 0 ? "yes" : "no"));
        Console.WriteLine("machine parts: " + gCalls + ", M " + mCalls + ", all " + N(Math.Round(enh.m_actPartsLen, 6)) +
                          " mm, work " + enh.m_nWorkCounter + ", rapid " + enh.m_nG00Counter);
        Console.WriteLine("at X " + N(Math.Round(pos.m_calcS.x, 6)) + " Y " + N(Math.Round(pos.m_calcS.y, 6)));

        Console.WriteLine("== destroy");
        SetCallbacks(0, false, false);
        for (uint c = 0; c < Tc.MAX_CORES; c++)
            Native.ToolChainCore_DestroyCNC(c);
        Console.WriteLine("destroyed, status " + Native.ToolChainCore_StatusCNC(0) + ", faults " + Callbacks.Faults);
        return 0;
    }
}
