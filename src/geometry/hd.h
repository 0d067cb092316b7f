/* One qualifier for code shared between the CPU and the GPU: the per-ray
 * traversal and intersection code is compiled as C for the CPU tests and as
 * CUDA device code for the GPU tracer, so both run exactly the same logic. */
#ifndef TT_GEOMETRY_HD_H
#define TT_GEOMETRY_HD_H

#ifdef __CUDACC__
#define TT_HD static inline __host__ __device__
#define TT_RESTRICT __restrict__
#else
#define TT_HD static inline
#define TT_RESTRICT restrict
#endif

/* Reads of the tree go through the read-only data cache on the GPU. Only in
 * nvcc's device pass (__CUDA_ARCH__): a TT_HD function is also compiled for
 * the host, where __ldg does not exist. */
#ifdef __CUDA_ARCH__
#define TT_LDG(p) __ldg(p)
#else
#define TT_LDG(p) (*(p))
#endif

#define TT_INF (__builtin_inff())

#endif
