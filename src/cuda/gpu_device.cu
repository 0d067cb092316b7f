/* Finding a usable device and turning CUDA errors into the library's
 * statuses and messages. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "cuda/gpu_internal.h"

static void put(char *buf, size_t size, const char *fmt, ...)
{
    if (!buf || size == 0) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, size, fmt, ap);
    va_end(ap);
}

static tt_status status_of(cudaError_t err)
{
    switch (err) {
    case cudaErrorMemoryAllocation:
        return TT_ERR_OUT_OF_MEMORY;
    case cudaErrorNoDevice:
    case cudaErrorInsufficientDriver:
    case cudaErrorInvalidDevice:
    case cudaErrorDevicesUnavailable:
    case cudaErrorNoKernelImageForDevice:
    case cudaErrorUnsupportedPtxVersion:
    case cudaErrorSystemDriverMismatch:
    case cudaErrorCompatNotSupportedOnDevice:
        return TT_ERR_NO_DEVICE;
    default:
        return TT_ERR_INTERNAL;
    }
}

tt_status tt_gpu_fail(tt_gpu_err *e, cudaError_t err, const char *what)
{
    tt_status st = status_of(err);
    if (st == TT_ERR_OUT_OF_MEMORY)
        put(e->msg, e->size, "GPU: out of device memory for the %s (%s)", what,
            cudaGetErrorString(err));
    else if (st == TT_ERR_NO_DEVICE)
        put(e->msg, e->size, "no usable CUDA device: %s (%s)", cudaGetErrorString(err), what);
    else
        put(e->msg, e->size, "GPU: %s failed: %s", what, cudaGetErrorString(err));
    return st;
}

tt_status tt_gpu_upload_array(tt_gpu_arrays *a, const void *src, size_t bytes, void **out,
                              tt_gpu_err *e, const char *what)
{
    *out = NULL;
    if (bytes == 0) return TT_OK; /* never read: the arrays' lengths say so */
    if (a->n == TT_GPU_MAX_ARRAYS) {
        put(e->msg, e->size, "GPU: too many device arrays for the %s", what);
        return TT_ERR_INTERNAL;
    }
    TT_GPU_TRY(e, cudaMalloc(out, bytes), what);
    a->p[a->n++] = *out;
    TT_GPU_TRY(e, cudaMemcpy(*out, src, bytes, cudaMemcpyHostToDevice), what);
    return TT_OK;
}

/* A kernel of this file's image: cudaFuncGetAttributes on it fails when
 * the device cannot run this build's code (an older architecture). */
__global__ void tt_gpu_probe_kernel(void) {}

tt_status tt_gpu_probe(char *name, size_t name_size, char *msg, size_t msg_size)
{
    int count = 0;
    put(name, name_size, "%s", "");
    cudaError_t err = cudaGetDeviceCount(&count);
    if (err != cudaSuccess) {
        put(msg, msg_size, "no usable CUDA device: %s", cudaGetErrorString(err));
        return TT_ERR_NO_DEVICE;
    }
    if (count < 1) {
        put(msg, msg_size, "no usable CUDA device: no CUDA-capable device is detected");
        return TT_ERR_NO_DEVICE;
    }
    cudaDeviceProp prop;
    err = cudaGetDeviceProperties(&prop, 0);
    if (err != cudaSuccess) {
        put(msg, msg_size, "no usable CUDA device: %s", cudaGetErrorString(err));
        return TT_ERR_NO_DEVICE;
    }
    put(name, name_size, "%s", prop.name);
    cudaFuncAttributes attr;
    err = cudaFuncGetAttributes(&attr, tt_gpu_probe_kernel);
    if (err != cudaSuccess) {
        put(msg, msg_size,
            "no usable CUDA device: %s (compute capability %d.%d) cannot run this build's "
            "code, built for sm_%s: %s",
            prop.name, prop.major, prop.minor, TT_CUDA_ARCHS, cudaGetErrorString(err));
        return TT_ERR_NO_DEVICE;
    }
    return TT_OK;
}
