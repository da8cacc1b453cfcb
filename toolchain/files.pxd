# Face of files.pyx: the files a host names (CompileFromFile's G-code, LoadFromIni's
# INI), read whole, regular files only, never blocking. Called by the exports (the
# check before a compilation starts), the core (the compile worker) and ini.pyx.

cdef enum:
    MAX_FILE_BYTES = 1 << 30        # 1 GiB: larger G-code or INI files are refused (ERR_FILE_TOO_LARGE)
    MAX_TABLE_BYTES = 64 << 20      # 64 MiB: larger tool or axis correction tables are refused
    FILE_READ_CHUNK = 1 << 16       # growth step for files whose size the open does not tell


# 0 when `path` can be read (else the error number); its bytes, NUL-terminated; the
# error of such a number for `path` recorded (-1)
cdef int file_error(ErrorInfo *err, int32_t number, int32_t file_idx, const char *path) noexcept nogil
cdef int32_t file_check_readable(const char *path) noexcept nogil
cdef char *read_whole_file(const char *path, size_t max_bytes, size_t *length, int32_t *error) noexcept nogil
