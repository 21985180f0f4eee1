#!/usr/bin/env bash
# Placeholder until 'make soak' is built.
echo "make soak: not built yet"
