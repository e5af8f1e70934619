/* Test-only stand-in for bcryptprimitives.dll under wine 8, which lacks it (every Windows 10 and
 * later has it). Rust's std imports ProcessPrng from it for its random seeds; this forwards to
 * RtlGenRandom (advapi32 SystemFunction036). It is used only to run the release checks under
 * wine and never goes into an FMU. */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length) {
    while (length > 0) {
        ULONG n = length > 0x10000000u ? 0x10000000u : (ULONG)length;
        if (!SystemFunction036(data, n)) return FALSE;
        data += n;
        length -= n;
    }
    return TRUE;
}
