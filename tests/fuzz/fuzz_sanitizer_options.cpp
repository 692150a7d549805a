// SPDX-License-Identifier: Apache-2.0
// Linked into every libFuzzer target (tests/fuzz/CMakeLists.txt): the first UBSan report stops the
// run like a crash, so the fuzzer writes the input and exits non-zero. The checks themselves stay
// recoverable in the code: the block after each check is one more coverage edge, which gives the
// fuzzer finer feedback than checks that only trap.

extern "C" const char* __ubsan_default_options() { return "halt_on_error=1:print_stacktrace=1"; }
