# tests/audit/audit.mk - generated invalid-argument and OOM suites, TSan
