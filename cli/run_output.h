/* The output folder of `elastopt run` (run_output.c): its lock, the files of an earlier
 * run, the per-step CSV logs and the restart file.
 *
 * A run folder holds
 *   run.lock        while a run writes into it: the writer's pid (O_CREAT|O_EXCL)
 *   run.json        how the run was set up: scene file (absolute) or built-in name, the
 *                   -o overrides, the resulting config document; read by --restart
 *   restart.dat     the state after the last completed step (rewritten atomically
 *                   every step), see eo_run_restart_write
 *   steps.csv       one row per completed step (STEPS_CSV_HEADER), exact numbers: the
 *                   summary of a continued run is rebuilt from it (rows of the 23 columns
 *                   before contact..total_energy, as older versions wrote, are read with
 *                   those four empty)
 *   iterations.csv  one row per solver iteration
 *   summary.json, NAME.pvd, frame_NNNNNN.vtu (NNNNNN = the step)
 * Both CSVs are appended and flushed after every step. */
#ifndef ELASTOPT_CLI_RUN_OUTPUT_H
#define ELASTOPT_CLI_RUN_OUTPUT_H
#include <stdio.h>

#include "cli.h"
#include "elastopt/sim.h"
#include "elastopt/step.h"

/* What `elastopt run` keeps of one completed step (a row of steps.csv). */
typedef struct eo_run_record {
    int step, iterations, reason;
    double t, time, wall, g, grad_norm;
    double cpu;           /* CPU seconds of the solving thread for the span of `time` (eo_sim_step_result.cpu_time) */
    long n_value, n_gradient, n_hessian, n_factor;
    long n_not_pd;        /* factorizations that found the matrix not positive definite */
    eo_step_stats stats;
    int entry;            /* the fallback-chain entry whose result was kept (0 = solver) */
    int n_entries;        /* entries run (0 when read back from steps.csv) */
    int entry_reason[EO_SIM_MAX_ENTRIES], entry_iterations[EO_SIM_MAX_ENTRIES];
    /* adaptive stepping (time.adaptive; eo_sim_step_result): attempts rejected, substeps
     * accepted, smallest step size tried (s); 0, 1, time.dt without substeps */
    int rejected, substeps;
    double min_substep;
} eo_run_record;

#define EO_RUN_STEPS_CSV_HEADER                                                                           \
    "step,t,iterations,reason,converged,solve_time,wall_time,g,grad_norm,n_value,n_gradient,n_hessian,"     \
    "n_factor,com_x,com_y,com_z,max_disp,min_J,inverted,kinetic,elastic,gravity_potential,entry,"         \
    "contact,potential,work_prescribed,total_energy,rejected,substeps,min_substep,n_not_pd,solve_cpu_time"
#define EO_RUN_ITER_CSV_HEADER "step,iteration,time,g,grad_norm,decrement,alpha,ls_evals,inverted,reason,entry"

/* The folder, locked. */
typedef struct eo_run_dir {
    char path[1024];
    char lock[1100];
    int locked;
} eo_run_dir;

/* Create the folder (and parents) if missing and lock it: run.lock created with
 * O_CREAT|O_EXCL holding our pid. EO_ERR_IO when the path cannot be a folder (a file,
 * device, FIFO, too long, unwritable) or when another live process holds the lock (the
 * message names its pid); a lock whose process is gone is replaced. */
int eo_run_dir_open(eo_ctx *ctx, const char *path, eo_run_dir *d);
/* Remove the lock (if held). */
void eo_run_dir_close(eo_run_dir *d);
/* Number of files of an earlier run in the folder (run.json, summary.json, the CSVs,
 * restart.dat and restart.dat.R-of-P, *.pvd, frame_*.vtu and their temporaries); the first few names into
 * names (may be NULL). */
int eo_run_dir_count_earlier(const eo_run_dir *d, char *names, size_t n);
/* Remove those files. */
int eo_run_dir_remove_earlier(eo_ctx *ctx, const eo_run_dir *d);
/* Remove frame_NNNNNN.vtu with NNNNNN > step. */
void eo_run_dir_remove_frames_after(const eo_run_dir *d, int step);

/* Frame file name of a step: frame_NNNNNN.vtu. */
void eo_run_frame_name(int step, char *buf, size_t n);

/* One row of steps.csv (no flush). */
/* A CSV number: exact in its shortest form (digits 17, eo_fmt_double) or %.6e; an empty string when v is not finite (no
 * output file holds a non-finite number; readers take an empty field as NAN). */
const char *eo_run_num(char buf[32], double v, int digits);
void eo_run_record_write(FILE *f, const eo_run_record *r);
/* Read steps.csv and iterations.csv of a run that completed `steps` steps and cut both
 * after the rows of step `steps` (dropping later rows and an incomplete last line, as a
 * killed run may leave); fills rec[0..steps-1] from steps.csv. EO_ERR_PARSE if
 * steps.csv does not hold exactly the rows 1..steps in order. Rows without the adaptive
 * columns (a run from before them) read as 0 rejected, 1 substep, min_substep NAN. */
int eo_run_logs_resume(eo_ctx *ctx, const eo_run_dir *d, int steps, eo_run_record *rec);

/* The restart file: a text header
 *     elastopt-restart 1
 *     step K            completed steps (the step index of the state)
 *     t HEXFLOAT        simulated time, exact (%a)
 *     nv N
 *     endian little|big
 *   then per array "array NAME COUNT\n" followed by COUNT raw doubles and "\n", then
 *   "end\n". Arrays are looked up by name: adding one (e.g. the previous positions of a
 *   multistep integrator) is one more entry in the caller's table; an optional array
 *   missing from the file is left as it is (present = 0), an unknown one is skipped.
 * Reading checks before trusting: the file's size against the most this scene's arrays
 * and header can take (Σ 8·count + 256 per array + 2 KiB, from stat, before allocating:
 * EO_ERR_RANGE), every header line, every array's count, and every value finite (a NaN
 * or Inf is EO_ERR_PARSE naming the array, the value's index, and for x and v the vertex
 * and coordinate). */
typedef struct eo_run_array {
    const char *name;
    double *data;     /* count values (caller's) */
    size_t count;
    int required;
    int present;      /* set by eo_run_restart_read */
} eo_run_array;
int eo_run_restart_write(eo_ctx *ctx, const char *path, int step, double t, int nv, const eo_run_array *a,
                         int na);
int eo_run_restart_read(eo_ctx *ctx, const char *path, int *step, double *t, int nv, eo_run_array *a, int na);

/* A distributed run (under mpirun, each rank simulating its part of the mesh) also keeps
 * one restart file per rank, restart.dat.R-of-P (R = the rank, P = the rank count), in
 * the same format: the rank's LOCAL state (x, v, the rank's share of the prescribed work,
 * the multistep history, the adaptive controller) in its local vertex order, and the
 * array "partition" = P, R, local vertices, local tets, global vertices, then the
 * identity of the rank's part (a 64-bit hash of its vertices' input numbers and
 * ownership, its local tets and rest positions) as two 32-bit halves. `--restart` under
 * mpirun on P ranks continues from them bit for bit; restart.dat (gathered on rank 0)
 * stays for readers of the whole state. */
void eo_run_restart_rank_name(int rank, int size, char *buf, size_t n);
/* The per-rank restart files in dir: *nranks = the largest P among restart.dat.R-of-P,
 * *nfiles = how many files with that P; returns the number of distinct P (0: none, > 1:
 * files of runs on different rank counts). */
int eo_run_restart_ranks(const char *dir, int *nranks, int *nfiles);

#endif
