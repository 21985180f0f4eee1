#!/usr/bin/env bash
# Placeholder until 'make bench' is built.
echo "make bench: not built yet"
