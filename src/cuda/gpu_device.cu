/* Finding a usable device and turning CUDA errors into the library's
 * statuses and messages. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

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
        put(e->msg, e->size, "no usable CUDA device: a device is present but failing (%s: %s)",
            what, cudaGetErrorString(err));
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

/* Whether this machine shows an NVIDIA device node, i.e. a GPU and its
 * kernel driver are present: CUDA failing then is a broken setup (driver
 * mismatch, failed initialisation, no kernel for the card), never "no
 * device", and is reported as such. */
static int device_node_present(void)
{
    return access("/dev/nvidia0", F_OK) == 0 || access("/proc/driver/nvidia/version", F_OK) == 0;
}

/* The probe's failure: "no device" when CUDA finds none and nothing on the
 * machine says there is one; otherwise "present but failing", with the
 * step that failed and CUDA's reason. */
static tt_status probe_fail(char *msg, size_t msg_size, const char *step, cudaError_t err)
{
    int absent = err == cudaErrorNoDevice || err == cudaErrorInsufficientDriver;
    if (absent && !device_node_present())
        put(msg, msg_size, "no usable CUDA device: no device here (%s: %s)", step,
            cudaGetErrorString(err));
    else
        put(msg, msg_size,
            "no usable CUDA device: a device is present but failing (%s: %s, CUDA error %d)",
            step, cudaGetErrorString(err), (int)err);
    return TT_ERR_NO_DEVICE;
}

tt_status tt_gpu_probe(char *name, size_t name_size, char *msg, size_t msg_size)
{
    int count = 0;
    put(name, name_size, "%s", "");
    cudaError_t err = cudaGetDeviceCount(&count);
    if (err != cudaSuccess) return probe_fail(msg, msg_size, "cudaGetDeviceCount", err);
    if (count < 1) return probe_fail(msg, msg_size, "cudaGetDeviceCount", cudaErrorNoDevice);
    cudaDeviceProp prop;
    err = cudaGetDeviceProperties(&prop, 0);
    if (err != cudaSuccess) return probe_fail(msg, msg_size, "cudaGetDeviceProperties", err);
    put(name, name_size, "%s", prop.name);
    cudaFuncAttributes attr;
    err = cudaFuncGetAttributes(&attr, tt_gpu_probe_kernel);
    if (err != cudaSuccess) {
        put(msg, msg_size,
            "no usable CUDA device: a device is present but failing: %s (compute capability "
            "%d.%d) cannot run this build's code, built for sm_%s: %s",
            prop.name, prop.major, prop.minor, TT_CUDA_ARCHS, cudaGetErrorString(err));
        return TT_ERR_NO_DEVICE;
    }
    return TT_OK;
}
