// Stage `sort_by_cell` (section 3 of the paper, the CUDA SDK "particles" scheme): a counting
// sort of the particles by the key of their cell in the dense grid (`GridGeometry`), done
// entirely on the device. Twin of `CpuBackend::sort_by_cell` (`Grid::sort`, `Fields::permute`),
// which radix-sorts over a sparse grid instead; the order within a cell is made deterministic
// here by `order_cells` (ascending particle id), so the result does not depend on the order in
// which the atomics ran.
//
// The host runs, in order, with `m = ncell + 1`:
//   cell_hash        n threads      key[i], cell_count[key]++        (cell_count zeroed, m entries)
//   scan_chunks      ceil(m/chunk)  exclusive scan of each chunk of cell_count into cell_start
//   scan_chunk_sums  1 thread       exclusive scan of the chunk totals
//   scan_add         m threads      cell_start[i] += chunk total before it; cell_start[ncell] == n
//   scatter          n threads      perm[slot] = i                    (cell_fill zeroed, ncell entries)
//   order_cells      ncell threads  each cell's perm range by ascending id
//   gather_*         n threads      every field, and key into cell_key: dst[i] = src[perm[i]]
#include "sph.cuh"

/// Key of particle i's cell, counted into its cell.
SPH_KERNEL(cell_hash)(u32 n, GridGeometry g, const float* __restrict__ pos, u32* __restrict__ key,
                      u32* __restrict__ cell_count) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    int cell[D];
    cell_of(g, vload(pos, i), cell);
    u32 k = cell_key(g, cell);
    key[i] = k;
    atomicAdd(&cell_count[k], 1u);
}

/// Thread t: exclusive scan of in[t*chunk .. min(m, (t+1)*chunk)) into out (which may be in),
/// and the chunk's total into chunk_sums[t].
SPH_KERNEL(scan_chunks)(u32 m, u32 chunk, const u32* in, u32* out, u32* __restrict__ chunk_sums) {
    u32 t = blockIdx.x * blockDim.x + threadIdx.x;
    unsigned long long start = (unsigned long long)t * chunk;
    if (start >= m) return;
    unsigned long long end = start + chunk < m ? start + chunk : m;
    u32 sum = 0u;
    for (unsigned long long i = start; i < end; ++i) {
        u32 v = in[i];  // read before the write: `in` may be `out`
        out[i] = sum;
        sum += v;
    }
    chunk_sums[t] = sum;
}

/// Thread 0 only: exclusive scan of the `chunks` chunk totals, in place.
SPH_KERNEL(scan_chunk_sums)(u32 chunks, u32* chunk_sums) {
    u32 t = blockIdx.x * blockDim.x + threadIdx.x;
    if (t != 0u) return;
    u32 sum = 0u;
    for (u32 c = 0; c < chunks; ++c) {
        u32 v = chunk_sums[c];
        chunk_sums[c] = sum;
        sum += v;
    }
}

/// out[i] += the total of the chunks before i's chunk.
SPH_KERNEL(scan_add)(u32 m, u32 chunk, u32* __restrict__ out, const u32* __restrict__ chunk_sums) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= m) return;
    out[i] += chunk_sums[i / chunk];
}

/// Places particle i in a free slot of its cell: perm (new index -> old index).
SPH_KERNEL(scatter)(u32 n, const u32* __restrict__ key, const u32* __restrict__ cell_start,
                    u32* __restrict__ cell_fill, u32* __restrict__ perm) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    u32 k = key[i];
    perm[cell_start[k] + atomicAdd(&cell_fill[k], 1u)] = i;
}

/// One thread per cell: insertion sort of perm[cell_start[c] .. cell_start[c+1]) by ascending
/// id[perm[k]] (ties, which distinct ids never have, by old index), so the order within a cell
/// is the same whatever order `scatter`'s atomics ran in.
SPH_KERNEL(order_cells)(u32 ncell, const u32* __restrict__ cell_start, const u32* __restrict__ id,
                        u32* __restrict__ perm) {
    u32 c = blockIdx.x * blockDim.x + threadIdx.x;
    if (c >= ncell) return;
    u32 a = cell_start[c], b = cell_start[c + 1];
    for (u32 k = a + 1; k < b; ++k) {
        u32 p = perm[k];
        u32 idp = id[p];
        u32 l = k;
        while (l > a) {
            u32 q = perm[l - 1];
            u32 idq = id[q];
            if (idq < idp || (idq == idp && q < p)) break;
            perm[l] = q;
            --l;
        }
        perm[l] = p;
    }
}

/// dst[i] = src[perm[i]] for a vector field (D floats per particle).
SPH_KERNEL(gather_vec)(u32 n, const u32* __restrict__ perm, const float* __restrict__ src,
                       float* __restrict__ dst) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    vstore(dst, i, vload(src, perm[i]));
}

/// dst[i] = src[perm[i]] for a scalar field.
SPH_KERNEL(gather_f32)(u32 n, const u32* __restrict__ perm, const float* __restrict__ src,
                       float* __restrict__ dst) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    dst[i] = src[perm[i]];
}

/// dst[i] = src[perm[i]] for an index field (kind, id, cell key).
SPH_KERNEL(gather_u32)(u32 n, const u32* __restrict__ perm, const u32* __restrict__ src,
                       u32* __restrict__ dst) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    dst[i] = src[perm[i]];
}
