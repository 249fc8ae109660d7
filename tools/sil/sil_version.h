/*
 * sil_version.h - the source revision drive_sil was built from: `git
 * describe --always --dirty` at build time, "unknown" outside git. The
 * definition is generated (tools/sil/module.mk, $(OUT)/gen/sil_version.c)
 * and rewritten only when the revision changes, so only it recompiles.
 */
#ifndef SIL_VERSION_H
#define SIL_VERSION_H

extern const char sil_revision[];

#endif /* SIL_VERSION_H */
