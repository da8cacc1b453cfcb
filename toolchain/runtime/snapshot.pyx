# The GetPos view of a core as a seqlock: writers (the worker that moves the
# position; an ending call once the worker is joined) serialise on write_lock and
# make `seq` odd while they copy; a reader copies without any lock and retries while
# a write overlapped. The copies go word by word through relaxed atomics, so the
# overlap a reader retries is not a data race in the C memory model (ThreadSanitizer
# agrees).
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
    static inline void tc_acquire_fence(void) { __atomic_thread_fence(__ATOMIC_ACQUIRE); }
    /* SnapshotData (SIMPLE_GM_PARAMS 616 + GM_PARAMS_ENHANCED 112 bytes) is copied
       in 8-byte words: tests/test_abi.py checks both sizes. */
    """
    void tc_snap_store(void *dst, const void *src, size_t n) nogil
    void tc_snap_load(void *dst, const void *src, size_t n) nogil
    uint32_t tc_seq_load(uint32_t *seq) nogil
    void tc_seq_begin(uint32_t *seq) nogil
    void tc_seq_end(uint32_t *seq) nogil
    void tc_acquire_fence() nogil

cdef void snapshot_init(Snapshot *snap) noexcept nogil:
    memset(snap, 0, sizeof(Snapshot))
    pthread_mutex_init(&snap.write_lock, NULL)
    snap.data.pos.m_fileIdx = -1


cdef void snapshot_publish(Snapshot *snap, const SnapshotData *data) noexcept nogil:
    pthread_mutex_lock(&snap.write_lock)
    tc_seq_begin(&snap.seq)
    tc_snap_store(&snap.data, data, sizeof(SnapshotData))
    tc_seq_end(&snap.seq)
    pthread_mutex_unlock(&snap.write_lock)


cdef void snapshot_read(Snapshot *snap, SnapshotData *out) noexcept nogil:
    """A consistent copy; never waits for a lock (a writer copies < 1 KB)."""
    cdef uint32_t before, after
    while True:
        before = tc_seq_load(&snap.seq)
        if before & 1:
            continue
        tc_snap_load(out, &snap.data, sizeof(SnapshotData))
        tc_acquire_fence()
        after = tc_seq_load(&snap.seq)
        if before == after:
            return
