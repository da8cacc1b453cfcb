# The GetPos view of a core: two slots, each a seqlock. Writers (the worker that
# moves the position; an ending call once the worker is joined) serialise on
# write_lock, copy into the slot readers are not directed to, then direct readers to
# it. A reader copies the current slot without any lock and retries only if a writer
# reused that slot meanwhile -- which needs a whole publication in between, so a writer
# preempted in the middle of a copy never holds readers up (on 2 cores a seqlock with
# one slot made GetPos wait a timeslice). The copies go word by word through relaxed
# atomics, so the overlap a reader retries is not a data race in the C memory model
# (ThreadSanitizer agrees).
#
# What the view shows is made in one place, getpos_publish, from where a run stands
# (core.pxd Standing) as its publisher knows it: the machine's pacer, the simulation,
# an ending call (ResetCNC, DestroyCNC), an addCode M function that waits. The layout
# of GetPos -- which position goes where, the cells of m_pars, the enhanced fields --
# is written here only.
from libc.string cimport memset, memcpy

cdef extern from *:
    """
    typedef unsigned long long tc_snap_word;
    static inline void tc_snap_store(void *dst, const void *src, size_t bytes) {
        tc_snap_word *d = (tc_snap_word *)dst;
        const tc_snap_word *s = (const tc_snap_word *)src;
        for (size_t i = 0; i < bytes / sizeof(tc_snap_word); i++)
            __atomic_store_n(&d[i], s[i], __ATOMIC_RELAXED);
    }
    static inline void tc_snap_load(void *dst, const void *src, size_t bytes) {
        tc_snap_word *d = (tc_snap_word *)dst;
        const tc_snap_word *s = (const tc_snap_word *)src;
        for (size_t i = 0; i < bytes / sizeof(tc_snap_word); i++)
            d[i] = __atomic_load_n(&s[i], __ATOMIC_RELAXED);
    }
    static inline unsigned tc_seq_load(unsigned *seq) { return __atomic_load_n(seq, __ATOMIC_ACQUIRE); }
    static inline void tc_seq_begin(unsigned *seq) {
        __atomic_store_n(seq, *seq + 1, __ATOMIC_RELAXED);
        __atomic_thread_fence(__ATOMIC_RELEASE);
    }
    static inline void tc_seq_end(unsigned *seq) { __atomic_store_n(seq, *seq + 1, __ATOMIC_RELEASE); }
    static inline void tc_seq_store(unsigned *p, unsigned v) { __atomic_store_n(p, v, __ATOMIC_RELEASE); }
    static inline void tc_acquire_fence(void) { __atomic_thread_fence(__ATOMIC_ACQUIRE); }
    /* SnapshotData (SIMPLE_GM_PARAMS 616 + GM_PARAMS_ENHANCED 112 bytes) is copied
       in 8-byte words: tests/test_abi.py checks both sizes. */
    """
    void tc_snap_store(void *dst, const void *src, size_t n) nogil
    void tc_snap_load(void *dst, const void *src, size_t n) nogil
    uint32_t tc_seq_load(uint32_t *seq) nogil
    void tc_seq_begin(uint32_t *seq) nogil
    void tc_seq_end(uint32_t *seq) nogil
    void tc_seq_store(uint32_t *p, uint32_t v) nogil
    void tc_acquire_fence() nogil

cdef void snapshot_init(Snapshot *snap) noexcept nogil:
    """An empty snapshot (file index -1 in both slots) and its writers' lock."""
    memset(snap, 0, sizeof(Snapshot))
    pthread_mutex_init(&snap.write_lock, NULL)
    snap.slots[0].data.pos.m_fileIdx = -1
    snap.slots[1].data.pos.m_fileIdx = -1
    standing_clear(&snap.shown)


cdef void _snapshot_publish(Snapshot *snap, const SnapshotData *data, const Standing *s) noexcept nogil:
    """Publishes `data` (made from `s`, kept as what is shown) for GetPos: written into the
    slot readers do not use, under its sequence counter, then made current; readers never wait."""
    cdef SnapshotSlot *slot
    cdef uint32_t next_slot
    pthread_mutex_lock(&snap.write_lock)
    next_slot = 1 - tc_seq_load(&snap.current)
    slot = &snap.slots[next_slot]
    tc_seq_begin(&slot.seq)
    tc_snap_store(&slot.data, data, sizeof(SnapshotData))
    tc_seq_end(&slot.seq)
    tc_seq_store(&snap.current, next_slot)
    memcpy(&snap.shown, s, sizeof(Standing))
    pthread_mutex_unlock(&snap.write_lock)


cdef void snapshot_read(Snapshot *snap, SnapshotData *out) noexcept nogil:
    """A consistent copy of the last publication; never waits for a lock."""
    cdef SnapshotSlot *slot
    cdef uint32_t before, after
    while True:
        slot = &snap.slots[tc_seq_load(&snap.current)]
        before = tc_seq_load(&slot.seq)
        if before & 1:
            continue                # reused while we looked: `current` has moved on
        tc_snap_load(out, &slot.data, sizeof(SnapshotData))
        tc_acquire_fence()
        after = tc_seq_load(&slot.seq)
        if before == after:
            return


cdef void core_read_position(Core *core, SIMPLE_GM_PARAMS *pos, GM_PARAMS_ENHANCED *enh) noexcept nogil:
    """GetPos: the last published snapshot into pos and enh (either may be NULL), with
    the status of the moment and, while the machine does not move, the host's feed
    override (a moving machine publishes the override of its own step)."""
    cdef SnapshotData view
    snapshot_read(&core.snap, &view)
    if pos != NULL:
        pos[0] = view.pos
    if enh != NULL:
        enh[0] = view.enh
        enh.m_statusCNC = core_status(core)
        if not machine_moving(enh.m_statusCNC):
            enh.m_relFeed = TC_ATOMIC_LOAD_D(&core.rel_feed)


# ------------------------------------------------------------------ what GetPos shows

cdef void standing_clear(Standing *s) noexcept nogil:
    """A machine standing at the origin that shows nothing but its position: no part
    (m_fileIdx -1), no cells (all 0), every counter, length and feed 0."""
    memset(s, 0, sizeof(Standing))
    s.part.m_fileIdx = -1
    s.g_cell = s.m_cell = INVALID_VALUE_F


cdef void standing_part(Standing *s, int32_t kind, int32_t func, bint waiting, const double *shift) noexcept nogil:
    """The part it stands in (a PartKind; any other value: none) shown in m_func and
    the cells: M functions as M + 10000, the G cell of a move or a dwell, the M cell
    of a waiting M function, the part's G92 shift (`shift`, ten axes; NULL: none);
    the other parts keep the part's m_func."""
    s.cells = True
    s.g_cell = s.m_cell = INVALID_VALUE_F
    s.shows_shift = shift != NULL
    if shift != NULL:
        memcpy(s.shift, shift, sizeof(s.shift))
    if kind == PART_MOTION or kind == PART_DWELL:
        s.part.m_func = func
        s.g_cell = <float>func
    elif kind == PART_MFUNC:
        s.part.m_func = func + 10000
        if waiting:
            s.m_cell = <float>func


cdef void getpos_publish(Snapshot *snap, const Standing *s) noexcept nogil:
    """GetPos where a run stands: the part's fields, m_calcS the output, m_calcE the
    drives; with cells, the cells the structures description gives the ten axes (X Y
    Z C B U V W A O at the output), the G92 shift (I J K L Q R D E S H), G, M, and N,
    T, P (cut and rapid length, the look-ahead's fill), the others absent; the
    enhanced fields. The one place that makes what GetPos shows."""
    cdef SnapshotData view
    cdef float *cells = <float *>&view.pos.m_pars
    cdef GM_PARAMS_ENHANCED *enh = &view.enh
    cdef int k
    view.pos = s.part
    memcpy(&view.pos.m_calcS, s.output, sizeof(P10DOUBLE))
    memcpy(&view.pos.m_calcE, s.drives, sizeof(P10DOUBLE))
    for k in range(26):
        cells[k] = INVALID_VALUE_F if s.cells else 0.0
    if s.cells:
        if s.shows_shift:
            for k in range(AXES):
                cells[_SHIFT_CELL[k]] = <float>s.shift[k]
        for k in range(AXES):
            cells[_AXIS_CELL[k]] = <float>s.output[k]
        view.pos.m_pars.G = s.g_cell
        view.pos.m_pars.M = s.m_cell
        view.pos.m_pars.N = <float>s.cut_len
        view.pos.m_pars.T = <float>s.rapid_len
        view.pos.m_pars.P = <float>s.fill
    enh.m_setFeed = s.set_feed
    enh.m_calcFeed = s.calc_feed
    enh.m_actFeed = s.act_feed
    enh.m_relFeed = s.rel_feed
    enh.m_actPartLen = s.part_len
    enh.m_actPartRemain = s.part_remain
    enh.m_actWorkPartsLen = s.cut_len
    enh.m_actG00PartsLen = s.rapid_len
    enh.m_actPartsLen = s.cut_len + s.rapid_len
    enh.m_nWorkCounter = s.counts.n_work
    enh.m_nG00Counter = s.counts.n_rapid
    enh.m_nG00ToWorkChanges = s.counts.rapid_to_work
    enh.m_nWorkToG00Changes = s.counts.work_to_rapid
    enh.m_nMCounter = s.counts.n_m
    enh.m_MasterEditorLine = s.master_line
    enh.m_MasterFileIdx = s.master_file
    enh.m_statusCNC = s.status
    enh.m_cncRunTime = s.run_time
    _snapshot_publish(snap, &view, s)


cdef void getpos_shown(Snapshot *snap, Standing *out) noexcept nogil:
    """The standing the last publication was made from."""
    pthread_mutex_lock(&snap.write_lock)
    memcpy(out, &snap.shown, sizeof(Standing))
    pthread_mutex_unlock(&snap.write_lock)


cdef extern from *:
    """
    /* m_pars cells of the ten axes X Y Z C B U V W A O (letter - 'A') */
    static const int tc_axis_cells[10] = {23, 24, 25, 2, 1, 20, 21, 22, 0, 14};
    /* m_pars cells of GetPos's G92 offsets of the ten axes: I J K L Q R D E S H */
    static const int tc_shift_cells[10] = {8, 9, 10, 11, 16, 17, 3, 4, 18, 7};
    """
    const int *_AXIS_CELL "tc_axis_cells"
    const int *_SHIFT_CELL "tc_shift_cells"
