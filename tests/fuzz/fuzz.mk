# tests/fuzz/fuzz.mk - libFuzzer targets (clang): make fuzz
