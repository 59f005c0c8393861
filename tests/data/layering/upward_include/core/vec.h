// A planted violation for tests/check_layering.py: core/ including a folder above it.
#pragma once
#include "renderer/render.h"
