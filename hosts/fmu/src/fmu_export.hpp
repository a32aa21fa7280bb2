// The functions an FMU's binary exports: the standard's names, visible; all
// else in the binary (the engine, yaml-cpp's users) stays hidden (fmu.map).
#pragma once

#define MH_FMU_EXPORT __attribute__((visibility("default")))
