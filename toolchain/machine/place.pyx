# Where the offline machine is on its program: Machine.place, one record (machine.pxd
# Place, its invariants stated there) that outlives the runs. Every change to it is
# one of these functions: dropped (place_forget), a motion part begins (the notifier:
# place_motion_begins), a run along the program ends (place_after_run, from the
# step's state), a connection puts it somewhere (place_connect). A run starts from it
# (place_resume); a backward run reads the history it retraces.
from libc.string cimport memset, memmove


cdef void place_forget(Place *p) noexcept nogil:
    """At the program's start, nothing run, no totals (the history's buffer kept)."""
    p.part = 0
    p.s = 0.0
    p.began = False
    p.current = PART_NONE
    p.n_history = 0
    p.history_lost = False
    p.cut_len = p.rapid_len = p.run_time = 0.0
    memset(&p.counts, 0, sizeof(RunCounts))


cdef inline bint place_at_start(const Place *p) noexcept nogil:
    """At the program's start with nothing run: a run from here is a run from the
    start (its placement may change)."""
    return p.part == 0 and p.s == 0.0 and p.n_history == 0


cdef inline bint place_inside_motion(const Place *p, const Program *prog) noexcept nogil:
    """It stands inside a motion part, some way along it (a backward run retraces the
    rest of that part first)."""
    return p.part < prog.n_parts and p.s > 0.0 and prog.parts[p.part].kind == PART_MOTION


cdef void place_push(Place *p, size_t part) noexcept nogil:
    """A motion part run, into the history (for backward runs): when HISTORY_DEPTH are
    held, the oldest tenth goes at once."""
    cdef size_t cap
    if p.n_history == HISTORY_DEPTH:
        memmove(p.history, p.history + HISTORY_DEPTH // 10,
                (HISTORY_DEPTH - HISTORY_DEPTH // 10) * sizeof(size_t))
        p.n_history -= HISTORY_DEPTH // 10
        p.history_lost = True
    if p.n_history == p.cap_history:
        cap = min(max(2 * p.cap_history, <size_t>1024), <size_t>HISTORY_DEPTH)
        if not resize(<void **>&p.history, cap, sizeof(size_t)):
            p.history_lost = True
            return
        p.cap_history = cap
    p.history[p.n_history] = part
    p.n_history += 1


cdef void place_motion_begins(Place *p, size_t part) noexcept nogil:
    """The notifier: a motion part began (forward); the one before it was run."""
    if p.current != PART_NONE:
        place_push(p, <size_t>p.current)
    p.current = <int64_t>part


cdef void place_resume(const Place *p, Motion *mo, bint backward) noexcept nogil:
    """A run along the program starts from the place: forward its first entry is the
    part it stands in, `s` along it, its start told if it was; backward the first
    entry is already what is left to retrace. The totals go on from the place's."""
    mo.d = p.s if not backward else 0.0
    mo.started = p.began and not backward
    mo.cut_len = p.cut_len
    mo.rapid_len = p.rapid_len
    mo.run_time = p.run_time


cdef void place_after_run(Place *p, Motion *mo, const Program *prog, bint backward, size_t fed_to,
                          size_t answered_m) noexcept nogil:
    """After a run along the program (the pacer joined, its events delivered): where
    the step stands, and the totals it reached. Forward: the entry it stands in and
    how far along it, else where the feeder was to go on (`fed_to`), else the
    program's end; the motion part it ran last goes into the history unless it stands
    in it; stopped at a waiting M function the driver was given (`answered_m`, the
    session's signalled part), the stop answered it: the place is after it. Backward:
    the entries retraced leave the history; it stands in the entry it is in (some way
    along it), else at the program's start, else (the history was cut) at the start
    of the last part it retraced."""
    cdef Entry *e
    cdef size_t removed
    cdef bint inside
    if backward:
        # entries [0, consumed) were retraced; the current one, if any, is the part it is in now
        removed = <size_t>mo.consumed + (1 if mo.count > 0 else 0)
        removed -= 1 if place_inside_motion(p, prog) and removed > 0 else 0
        p.n_history -= min(removed, p.n_history)
        if mo.count > 0:
            e = motion_entry(mo, 0)
            p.part = e.part
            p.s = e.s_from - mo.d
            p.began = True
        elif not p.history_lost:
            p.part = 0                  # back at the start: a run begins with the program again
            p.s = 0.0
            p.began = False
        elif mo.consumed > 0:
            p.part = mo.ring[(mo.consumed - 1) % LOOK_RING].part
            p.s = 0.0
            p.began = False
        p.current = p.part if p.began else PART_NONE
    else:
        if mo.count > 0:
            e = motion_entry(mo, 0)
            p.part = e.part
            p.s = mo.d
            p.began = mo.started
        elif not mo.complete:           # it stands where the feeder is to go on
            p.part = fed_to
            p.s = 0.0
            p.began = False
        else:
            p.part = prog.n_parts
            p.s = 0.0
            p.began = False
        inside = mo.count > 0 and p.began and motion_entry(mo, 0).kind == PART_MOTION
        if not inside and p.current != PART_NONE:
            place_push(p, <size_t>p.current)        # it stands after the part it ran last
            p.current = PART_NONE
        if mo.count > 0 and mo.state == MS_STOPPED:
            e = motion_entry(mo, 0)
            if e.kind == PART_MFUNC and e.waits and answered_m == e.part:
                p.part = e.part + 1
                p.s = 0.0
                p.began = False
    p.cut_len = mo.cut_len
    p.rapid_len = mo.rapid_len
    p.run_time = mo.run_time


cdef void place_connect(Place *p, const Program *prog, size_t part, double s) noexcept nogil:
    """A connection's place: `s` along `part` (begun when s > 0), the motion parts
    before it remembered for backward runs (the last HISTORY_DEPTH of them)."""
    cdef size_t k, first
    p.part = part
    p.s = s
    p.began = s > 0.0
    p.n_history = 0
    first = part - HISTORY_DEPTH if part > HISTORY_DEPTH else 0
    p.history_lost = first > 0
    for k in range(first, part):
        if prog.parts[k].kind == PART_MOTION:
            place_push(p, k)
    p.current = <int64_t>part if p.began and prog.parts[part].kind == PART_MOTION else PART_NONE
