/* Wine 8 (Debian 12) lacks bcryptprimitives.dll, which Rust's std on Windows imports for
   ProcessPrng. This stand-in answers it with RtlGenRandom (advapi32), as Windows does. */
#include <windows.h>
#define SystemFunction036 NTAPI SystemFunction036
#include <ntsecapi.h>
#undef SystemFunction036
__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T len) {
    return RtlGenRandom(data, (ULONG)len);
}
