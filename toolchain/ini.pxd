# Face of ini.pyx: the vendor's Windows-syntax INI files, each entry handed to a
# visitor. Called by the exports (LoadFromIni, with parameters.pyx's visitor).

# 0 to go on; anything else stops ini_read, which returns it
ctypedef int32_t (*ini_visitor)(void *ctx, const char *section, const char *key, const char *value,
                                int32_t line) noexcept nogil


# every key of the file to `visit`: 0, or the error number that stopped it
cdef int32_t ini_read(const char *path, ini_visitor visit, void *ctx) noexcept nogil
