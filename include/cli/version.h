/* version.h: rodsim's version, in one place (`rodsim --version`,
 * `rodsim version`). Raise it with each release. */
#ifndef RODSIM_VERSION_H
#define RODSIM_VERSION_H

#define RODSIM_VERSION "0.9.0"

#endif
