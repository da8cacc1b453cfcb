# The GetPos view of a core: two slots, each a seqlock. Writers (the worker that
# moves the position; an ending call once the worker is joined) serialise on
# write_lock, copy into the slot readers are not directed to, then direct readers to
# it. A reader copies the current slot without any lock and retries only if a writer
# reused that slot meanwhile -- which needs a whole publication in between, so a writer
# preempted in the middle of a copy never holds readers up (on 2 cores a seqlock with
# one slot made GetPos wait a timeslice). The copies go word by word through relaxed
# atomics, so the overlap a reader retries is not a data race in the C memory model
# (ThreadSanitizer agrees).
from libc.string cimport memset

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


cdef void snapshot_publish(Snapshot *snap, const SnapshotData *data) noexcept nogil:
    """Publishes `data` for GetPos: written into the slot readers do not use, under its sequence
    counter, then made current; readers never wait."""
    cdef SnapshotSlot *slot
    cdef uint32_t next_slot
    pthread_mutex_lock(&snap.write_lock)
    next_slot = 1 - tc_seq_load(&snap.current)
    slot = &snap.slots[next_slot]
    tc_seq_begin(&slot.seq)
    tc_snap_store(&slot.data, data, sizeof(SnapshotData))
    tc_seq_end(&slot.seq)
    tc_seq_store(&snap.current, next_slot)
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
