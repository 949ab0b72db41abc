/* DEMLink C ABI: the co-simulation client for Modelica-style tools (docs/c_abi.md).
 *
 * Why a C ABI: Modelica external functions, Fortran, Python ctypes and most simulation
 * tools can call plain C; none can catch C++ exceptions. Every function here catches
 * everything, returns a status code (dl_status) and keeps the message of the last failure
 * per client (dl_last_error). It is a thin layer over the C++ library demlink::client;
 * there is no second protocol implementation.
 *
 * Why handles are void: Modelica passes ExternalObjects as void*. Some tools emit their own
 * prototype of each external function; a distinct struct type here would then conflict.
 * The library checks a tag in every handle and answers DL_ERR_ARGUMENT for a package
 * passed as a client and vice versa.
 *
 * Two styles, not to be mixed on one client:
 *  1. Generic packages, as in the coupling paper: dl_set_data(pkg, ints, reals, strings),
 *     dl_send_package, dl_recv_package, dl_get_ints/reals/strings. The meaning of each
 *     array per component kind is listed below ("Generic layout").
 *  2. Typed helpers per kind: dl_declare_<kind>(...) and dl_<kind>_exchange / _read(...).
 *
 * Components are addressed by a client-local handle: 0 for the first component declared
 * on this client, 1 for the second, ... (not the server's id).
 *
 * Exchange orders (dl_set_exchange_order). The server advances the world once EVERY
 * component due at a step (of every connection) has sent its package, and answers each
 * component at the END of its interval. A typed exchange call at sample t_k with interval h:
 *  - DL_ORDER_SEND_FIRST (default): sends the inputs at t_k, then receives and returns the
 *    outputs of [t_k, t_k + h] (the outputs at t_k + h, as the C++ client's exchange() and
 *    FMI 2.0 Co-Simulation define them). The call waits for its own answer, so it suits a
 *    thread whose only exchanged component due at t_k is this one; with another component
 *    of the same client due at t_k the call is refused (DL_ERR_STATE), and with another
 *    client's component in the same thread it would wait for the timeout.
 *  - DL_ORDER_SEND_FIRST_SPLIT: the same timing in two calls per sample, for several
 *    components (and clients) stepped by one thread, e.g. a Modelica model: the sample's
 *    first call sends the inputs at t_k (its outputs stay those of the previous sample);
 *    once EVERY component of the thread has made its first call, each one's second call
 *    receives and returns [t_k, t_k + h] (its inputs are not used). A component whose
 *    interval is longer than the simulation's shortest gets its answer only while the
 *    faster ones step on: its second call keeps the outputs, and the first call of its
 *    next sample receives the interval that ended there before sending.
 *  - DL_ORDER_RECEIVE_FIRST: one call that receives the interval that ENDED at t_k (at the
 *    first call: the initial outputs of Compiled), then sends the inputs at t_k. Never
 *    waits for a component that has not run yet, in any call order, but the outputs lag
 *    one interval: a body integrated with them feels the force of the interval before,
 *    which needs about a 10x shorter interval for the same error (docs/accuracy.md,
 *    "Choosing a communication interval").
 * The initial algorithm of a Modelica model only connects and declares: waiting for
 * Compiled there would block before the other components have declared. The first
 * exchange waits for Compiled (or call dl_wait_compiled explicitly).
 *
 * Generic layout ("[i]" = index; NaN in an optional real = "not given" / default):
 *
 *  Declare package (a package WITH strings is a declaration):
 *   strings[0] = kind, strings[1] = name; reals[0] = communication interval [s] (0: never
 *   exchanged). Per kind:
 *   simulation_box : reals[1] time step [s] (NaN: default), [2] end time [s],
 *                    [3..5] gravity [m/s^2], [6..8] bounds lower, [9..11] bounds upper [m]
 *                    (bounds only when nReals >= 12), [12] VTK output interval [s]
 *                    (optional; NaN: default), [13] restitution tolerance (optional),
 *                    [14] max impact velocity [m/s] (optional), [15] coarse graining
 *                    factor >= 1 (optional), [16] watchdog overlap limit, a fraction of
 *                    the smaller radius in (0, 2] (optional; default 0.5), [17] modulus
 *                    scale, a softening factor of every Young's modulus in (0, 1]
 *                    (optional; default 1); ints[0]
 *                    expected component count (<= 0:
 *                    none), ints[1] engine threads (optional; negative: default 1, 0:
 *                    the usable CPUs less the load average), ints[2] contact model and ints[3] integrator (optional; as
 *                    dl_declare_simulation_box_ex), ints[4] fidelity preset (optional;
 *                    0 none, 1 draft, 2 engineering, 3 validation);
 *                    strings[2..] expected component names.
 *   material       : strings[2] database name ("" none); reals[1] density [kg/m^3],
 *                    [2] Young's modulus [Pa], [3] Poisson ratio, [4] restitution,
 *                    [5] sliding friction, [6] rolling friction (each NaN/omitted: default).
 *   plane          : strings[2] material; reals[1..3] point [m], [4..6] normal.
 *   single_particle: strings[2] material; reals[1..3] position [m], [4..6] velocity [m/s],
 *                    [7] diameter [m].
 *   particle_system: strings[2] CSV file path on the server; ints[0] = 1: strings[2] is a
 *                    checkpoint file instead.
 *   particle_source: strings[2] material, strings[3] attached mesh ("" none);
 *                    reals[1..3] box centre [m], [4..6] half extents [m], [7] r_min,
 *                    [8] r_max [m], [9] rate [1/s] (NaN: not given), [10] rate [kg/s]
 *                    (NaN: not given), [11..13] velocity [m/s], [14] start time [s],
 *                    [15] stop time [s] (NaN: never); ints[0] seed; strings[4] a
 *                    clump_template the source pours instead of spheres ("" or omitted:
 *                    spheres).
 *   clump_template : reals[1..] (x, y, z, radius) [m] per sphere, offsets from the
 *                    clump's reference point; at least one sphere.
 *   particle_sink,
 *   region_sensor  : ints[0] shape: 0 box, 1 sphere; box: reals[1..3] centre, [4..6] size [m],
 *                    [7..10] orientation w x y z (optional, NaN: none); sphere: reals[1..3]
 *                    centre, [4] radius [m]; both: [11..13] constant velocity [m/s] of a
 *                    region not attached (optional, NaN: fixed; centre is then at t = 0);
 *                    strings[2] attached body ("" none).
 *   flow_sensor    : ints[0] shape: 0 rectangle, 1 disc; reals[1..3] centre, [4..6] normal;
 *                    rectangle: [7] length, [8] width [m], [9..11] length axis (optional,
 *                    NaN: any); disc: [7] radius [m]; both: [12..14] constant velocity
 *                    [m/s] (optional, NaN: fixed); strings[2] attached body ("" none).
 *   pit_generator  : strings[2] material; reals[1..3] lower, [4..6] upper corner [m],
 *                    [7] r_min, [8] r_max, [9] target height [m]; ints[0] seed; clods
 *                    (optional): reals[10] fraction [-], [11] radius [m], strings[3] the
 *                    parallel_bonds that join them; strings[4] a clump_template
 *                    the bed is made of ("" or omitted: spheres).
 *   parallel_bonds : reals[1] kn, [2] ks [Pa/m], [3] tensile, [4] shear strength [Pa],
 *                    [5] gap tolerance [m], [6] radius multiplier, [7] create time [s],
 *                    [8] fraction (each NaN or omitted: default); ints[0] seed; ints[1]
 *                    region as dl_region_kind: 0 everywhere, 1 box (reals[9..11] centre,
 *                    [12..14] size [m], [15..18] orientation w x y z, optional), 2 sphere
 *                    (reals[9..11] centre, [12] radius [m]); with ints[1], strings[2] is
 *                    the mesh body the region rides on ("" fixed) and strings[3..] the
 *                    material names (none: any). Without ints[1]: reals[9..14] a box's
 *                    centre and size (omitted: everywhere), strings[2..] the materials.
 *   rigid_body     : strings[2] material, strings[3] geometry text; ints[0] geometry:
 *                    0 STL file on the server (strings[3] = path), 1 box (reals[11..13]
 *                    size [m]), 2 STL file on the client (strings[3] = path; its bytes are
 *                    sent); ints[1] motion: 0/1 PREDICTED, 2 LAGGED; reals[1..3] reference
 *                    point [m], [4..6] initial position [m], [7..10] initial orientation
 *                    w x y z.
 *   particle_view  : ints[0] max particles per package (0: 10000).
 *
 *  Input package (a package WITHOUT strings): ints[0] = component handle; the step is the
 *  component's next due step (kept by the library). Per kind:
 *   rigid_body     : reals = x y z qw qx qy qz vx vy vz wx wy wz (13) [m, -, m/s, rad/s].
 *   simulation_box : reals[0..2] new gravity [m/s^2] (omitted or NaN: unchanged);
 *                    reals[3..14] frame motion: linear acceleration, angular velocity,
 *                    angular acceleration, origin (when nReals >= 15).
 *   region_sensor  : each omitted or NaN: unchanged; reals[0..2] centre [m], [3..6]
 *                    orientation w x y z, [7..9] box size [m], [10] sphere radius [m].
 *   particle_source: reals[0] on (1) / off (0), [1] rate in the declared unit (NaN: unchanged).
 *   particle_sink  : reals[0] on (1) / off (0), [1..3] centre [m] (NaN: unchanged).
 *   others         : no reals (the empty package says "go on").
 *
 *  Output package (dl_recv_package, dl_get_outputs): strings[0] = kind, strings[1] = name;
 *  ints[0] = component handle, ints[1] = step the interval ended at; then per kind:
 *   simulation_box : ints[2] particle count; reals = time [s], total mass [kg],
 *                    kinetic energy [J], step rate [1/s].
 *   rigid_body     : reals = mean force(3) [N], mean torque(3) [N m], force(3), torque(3)
 *                    at the interval's end, position(3) [m], orientation w x y z (4) (19).
 *   particle_source,
 *   particle_sink  : ints[2..4] = count during the interval, since step 0, shortfall since
 *                    step 0 (sources only); reals = the corresponding masses [kg].
 *   region_sensor  : ints[2] count, ints[3] intact and ints[4] broken parallel bonds whose
 *                    midpoint is inside; reals = mass [kg], centre of mass(3) [m],
 *                    mean velocity(3) [m/s] (zeros when empty: ints[2] is 0).
 *   flow_sensor    : ints[2..5] crossings: positive interval, negative interval, positive
 *                    total, negative total; reals = the corresponding masses [kg].
 *   particle_view  : ints[2] particles in the world, ints[3] stride, ints[4..] ids (the
 *                    particles whose id is a multiple of the stride, increasing);
 *                    reals = positions x y z per particle [m], then radii [m], then
 *                    velocities x y z per particle [m/s].
 *   (others are never exchanged)
 */
#ifndef DEMLINK_DEMLINK_C_H
#define DEMLINK_DEMLINK_C_H

#if defined(DEMLINK_C_BUILDING) && defined(_WIN32)
#define DL_API __declspec(dllexport)
#elif defined(DEMLINK_C_BUILDING)
#define DL_API __attribute__((visibility("default")))
#else
#define DL_API
#endif

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Version of the library, e.g. "0.1.0" (the project's); the ABI version is the SONAME's
 * number (libdemlink_c.so.1). ABI 1 changed the seed arguments from int to uint64_t. */
DL_API const char* dl_version(void);

typedef void dl_client;  /* one connection and its components */
typedef void dl_package; /* a generic send/receive buffer: ints, reals, strings */

/* Status codes returned by every int function. */
enum dl_status {
  DL_OK = 0,
  DL_ERR_CONNECT = 1,  /* cannot connect, connection lost, or bad bytes from the server */
  DL_ERR_TIMEOUT = 2,  /* no answer within the timeout (the connection is then closed) */
  DL_ERR_SERVER = 3,   /* the server sent Error: see dl_last_server_error_code/_field */
  DL_ERR_ARGUMENT = 4, /* null or wrong handle, bad layout, unknown kind, bad index */
  DL_ERR_STATE = 5,    /* not allowed now (e.g. declare after compile, exchange before connect) */
  DL_ERR_FINISHED = 6, /* the simulation has ended: dl_finished_reason */
  DL_ERR_CAPACITY = 7, /* an output array is too small (the prefix that fits is copied) */
  DL_ERR_INTERNAL = 8  /* a bug or out of memory; dl_last_error says what */
};

/* --- Client and connection -------------------------------------------------------- */
DL_API dl_client* dl_client_create(void); /* NULL only when out of memory */
DL_API void dl_client_destroy(dl_client* client); /* closes the connection; NULL is ignored */
/* Bound of every blocking call [s]; default 30. */
DL_API int dl_set_timeout(dl_client* client, double seconds);
/* Connects, Hello -> Welcome. token may be NULL or "" (no token). Calling it again on a
 * connected client with the same host, port and name is a no-op (a tool that repeats its
 * initialisation); with others it is DL_ERR_STATE. */
DL_API int dl_connect_to_host(dl_client* client, const char* host, int port, const char* client_name,
                              const char* token);
/* Message of the last failure on this client ("" when none); valid until the next call. */
DL_API const char* dl_last_error(const dl_client* client);
/* demlink.v1.Error.Code of the last DL_ERR_SERVER (0 when none), its field and component. */
DL_API int dl_last_server_error_code(const dl_client* client);
DL_API const char* dl_last_server_error_field(const dl_client* client);
DL_API const char* dl_last_server_error_component(const dl_client* client);

/* --- Generic packages ---------------------------------------------------------------- */
DL_API dl_package* dl_package_create(void);
DL_API void dl_package_destroy(dl_package* package);
/* Replaces the package's content (copies). Arrays may be NULL when their count is 0. */
DL_API int dl_set_data(dl_package* package, const long long* ints, int nInts, const double* reals, int nReals,
                       const char* const* strings, int nStrings);
/* Copy-out: *count = the package's size; copies min(size, capacity) values. out == NULL
 * (capacity 0) only asks the size. DL_ERR_CAPACITY when out is too small. Strings are
 * pointers into the package, valid until it is next changed. */
DL_API int dl_get_ints(const dl_package* package, long long* out, int capacity, int* count);
DL_API int dl_get_reals(const dl_package* package, double* out, int capacity, int* count);
DL_API int dl_get_strings(const dl_package* package, const char** out, int capacity, int* count);
/* Declare package: declares a component (before compile). Input package: sends the
 * component's inputs for its due step (its previous answer must have been received). */
DL_API int dl_send_package(dl_client* client, const dl_package* package);
/* The next answer of any component of this client, in the output layout (waits for
 * Compiled first if needed). DL_ERR_STATE when no package is in flight. */
DL_API int dl_recv_package(dl_client* client, dl_package* package);
/* The latest outputs of a component (after compile: the initial outputs) without waiting. */
DL_API int dl_get_outputs(dl_client* client, int component, dl_package* package);

/* --- Session --------------------------------------------------------------------------- */
/* This client declares nothing more (DeclarationsDone). Once every client of the
 * simulation has called it, the server compiles: no expected component count and no quiet
 * period. Does not wait; idempotent; a no-op after the compile. A client with all the
 * model's components calls it at the end of its initialisation. */
DL_API int dl_declarations_done(dl_client* client);
DL_API int dl_wait_compiled(dl_client* client); /* no-op once compiled */
DL_API int dl_time_step(dl_client* client, double* seconds);
DL_API int dl_component_interval_steps(dl_client* client, int component, long long* steps);
/* The compile report as printed by the server ("" before compile). */
DL_API const char* dl_compile_report(const dl_client* client);
/* Sends Bye and returns without waiting (Modelica terminal(): other clients in the same
 * thread still have to say Bye). No-op when the simulation already finished. */
DL_API int dl_finish(dl_client* client, const char* reason);
/* Blocks until Finished (after dl_finish, or when the server ends the simulation). */
DL_API int dl_wait_finished(dl_client* client);
DL_API const char* dl_finished_reason(const dl_client* client); /* "" until finished */

/* --- Typed declarations (send Declare at once; *component receives the handle) ------------
 * interval: communication interval [s], 0: never exchanged. NaN or a negative value in an
 * optional physical argument means "not given" (the server's default). Vectors are
 * x y z; poses are x y z qw qx qy qz. Pointers to optional vectors may be NULL.
 * Declaring a component again with the same name and the same values (a tool repeating
 * its initialisation) returns the first handle and sends nothing, even after the compile;
 * the same name with other values is DL_ERR_STATE.
 * simulation box: endTime NaN or <= 0: no end time, the run ends when every client has
 * called dl_finish (Bye); expectedCount <= 0: none (use dl_declarations_done). */
DL_API int dl_declare_simulation_box(dl_client* client, const char* name, double interval, double timeStep,
                                     double endTime, const double gravity[3], const double boundsLower[3],
                                     const double boundsUpper[3], int expectedCount, int* component);
/* The simulation box with the speed/accuracy settings (docs/physics.md): contactModel
 * 0 default, 1 Hertz-Mindlin, 2 linear spring-dashpot; integrator 0 default, 1 velocity
 * Verlet, 2 explicit Euler; maxImpactVelocity [m/s] (NaN or <= 0: default 2);
 * restitutionTolerance: the largest restitution error the server's time-step limit allows [-]
 * (NaN or negative: the server's default 0.01; larger accepts a larger time step, trading
 * accuracy for speed); vtkInterval
 * [s] (NaN or negative: default, 0: first and last frame only); threads (negative: default 1,
 * 0: the usable CPUs less the load average); frame = the frame's linear acceleration(3) [m/s^2], angular velocity(3)
 * [rad/s], angular acceleration(3) [rad/s^2], origin(3) [m] (NULL: inertial frame). No
 * expected count: use dl_declarations_done. */
DL_API int dl_declare_simulation_box_ex(dl_client* client, const char* name, double interval, double timeStep,
                                        double endTime, const double gravity[3], const double boundsLower[3],
                                        const double boundsUpper[3], int contactModel, int integrator,
                                        double maxImpactVelocity, double restitutionTolerance,
                                        double vtkInterval, int threads,
                                        const double frame[12], int* component);
DL_API int dl_declare_material(dl_client* client, const char* name, const char* databaseName, double density,
                               double youngsModulus, double poissonRatio, double restitution,
                               double slidingFriction, double rollingFriction, int* component);
DL_API int dl_declare_plane(dl_client* client, const char* name, const double point[3], const double normal[3],
                            const char* material, int* component);
DL_API int dl_declare_single_particle(dl_client* client, const char* name, const char* material,
                                      const double position[3], const double velocity[3], double diameter,
                                      int* component);
/* motion: 0 or 1 PREDICTED, 2 LAGGED. stlFile is a path on the SERVER. */
DL_API int dl_declare_rigid_body_stl(dl_client* client, const char* name, double interval, const char* stlFile,
                                     const char* material, const double referencePoint[3], const double pose[7],
                                     int motion, int* component);
/* A CAD part: localStlFile is a path on THIS computer; its bytes are sent to the server. */
DL_API int dl_declare_cad_part(dl_client* client, const char* name, double interval, const char* localStlFile,
                               const char* material, const double referencePoint[3], const double pose[7],
                               int motion, int* component);
/* Particles from a file on the server: a CSV (checkpoint 0) or a checkpoint (1). */
DL_API int dl_declare_particle_system(dl_client* client, const char* name, const char* file, int checkpoint,
                                      int* component);
DL_API int dl_declare_rigid_body_box(dl_client* client, const char* name, double interval, const double size[3],
                                     const char* material, const double pose[7], int motion, int* component);
DL_API int dl_declare_region_sensor_box(dl_client* client, const char* name, double interval,
                                        const double centre[3], const double size[3], const char* attachedTo,
                                        int* component);
/* orientation w x y z (NULL: none); attachedTo "" or NULL: fixed in the world. */
DL_API int dl_declare_region_sensor_box_oriented(dl_client* client, const char* name, double interval,
                                                 const double centre[3], const double size[3],
                                                 const double orientation[4], const char* attachedTo,
                                                 int* component);
DL_API int dl_declare_region_sensor_sphere(dl_client* client, const char* name, double interval,
                                           const double centre[3], double radius, const char* attachedTo,
                                           int* component);
DL_API int dl_declare_flow_sensor_disc(dl_client* client, const char* name, double interval,
                                       const double centre[3], const double normal[3], double radius,
                                       const char* attachedTo, int* component);
/* length along lengthAxis (NULL: the server's default axis), width across [m]. */
DL_API int dl_declare_flow_sensor_rectangle(dl_client* client, const char* name, double interval,
                                            const double centre[3], const double normal[3], double length,
                                            double width, const double lengthAxis[3], const char* attachedTo,
                                            int* component);
/* ratePerSecond / rateKgPerSecond: give exactly one (the other negative). */
DL_API int dl_declare_particle_source_box(dl_client* client, const char* name, double interval,
                                          const char* material, const double centre[3],
                                          const double halfExtents[3], double rMin, double rMax,
                                          double ratePerSecond, double rateKgPerSecond, const double velocity[3],
                                          uint64_t seed, int* component);
/* The general source (docs/sources.md). region 0 box: regionParams = centre(3), half
 * extents(3) [m]; 1 disc: centre(3), normal(3), radius, thickness (0: thin) [m].
 * sizeKind / sizeParams [m, -]: 0 one radius {r}; 1 uniform {r_min, r_max}; 2 linear pdf
 * {r_min, r_max, weight at r_min, weight at r_max}; 3 truncated normal {mean, std, r_min,
 * r_max}; 4 discrete {radius, weight, radius, weight, ...} (nSizeParams = 2 x radii). */
DL_API int dl_declare_particle_source(dl_client* client, const char* name, double interval, const char* material,
                                      int region, const double* regionParams, int sizeKind,
                                      const double* sizeParams, int nSizeParams, double ratePerSecond,
                                      double rateKgPerSecond, const double velocity[3], uint64_t seed,
                                      int* component);
DL_API int dl_declare_particle_sink_box(dl_client* client, const char* name, double interval,
                                        const double centre[3], const double size[3], int* component);
DL_API int dl_declare_particle_sink_box_oriented(dl_client* client, const char* name, double interval,
                                                 const double centre[3], const double size[3],
                                                 const double orientation[4], const char* attachedTo,
                                                 int* component);
DL_API int dl_declare_particle_sink_sphere(dl_client* client, const char* name, double interval,
                                           const double centre[3], double radius, const char* attachedTo,
                                           int* component);
DL_API int dl_declare_pit_generator(dl_client* client, const char* name, const char* material,
                                    const double lower[3], const double upper[3], double rMin, double rMax,
                                    double targetHeight, uint64_t seed, int* component);
DL_API int dl_declare_particle_view(dl_client* client, const char* name, double interval, int maxCount,
                                    int* component);
/* Parallel bonds (docs/reference/parallel_bonds.md), declared only. properties = normal and
 * shear stiffness per area [Pa/m], tensile and shear strength [Pa], gap tolerance [m],
 * radius multiplier [-] (NaN: 1), create time [s], fraction of the candidate pairs [-]
 * (NaN: 1) -- 8 values; box = centre(3), size(3) [m] of the region (NULL: everywhere);
 * materials = material names separated by spaces ("" or NULL: any); seed of the fraction.
 * The server checks the values when the scene compiles and names the bad field. */
DL_API int dl_declare_parallel_bonds(dl_client* client, const char* name, const double properties[8],
                                     const double box[6], const char* materials, uint64_t seed, int* component);
/* Where a parallel-bond rule bonds (dl_declare_parallel_bonds_region). */
enum dl_region_kind {
  DL_REGION_EVERYWHERE = 0, /* every pair */
  DL_REGION_BOX = 1,        /* pairs with both centres in the box */
  DL_REGION_SPHERE = 2      /* pairs with both centres in the sphere */
};
/* dl_declare_parallel_bonds with any region the scene accepts: regionKind a dl_region_kind;
 * centre [m] (unused for DL_REGION_EVERYWHERE); a box's size [m] and orientation w x y z
 * (NULL: unrotated); a sphere's radius [m]; attachedTo: a mesh body the region rides on, its
 * centre then in that body's frame ("" or NULL: fixed). Other arguments as
 * dl_declare_parallel_bonds. */
DL_API int dl_declare_parallel_bonds_region(dl_client* client, const char* name, const double properties[8],
                                            int regionKind, const double centre[3], const double size[3],
                                            const double orientation[4], double radius, const char* attachedTo,
                                            const char* materials, uint64_t seed, int* component);
/* dl_declare_pit_generator with clods: clods = fraction [-] of the bed's spheres grouped into
 * clods, clod radius [m]; bondsName = the parallel bonds that join them
 * (docs/reference/pit_generator.md). */
DL_API int dl_declare_pit_generator_clods(dl_client* client, const char* name, const char* material,
                                          const double lower[3], const double upper[3], double rMin, double rMax,
                                          double targetHeight, uint64_t seed, const double clods[2],
                                          const char* bondsName, int* component);
/* Deformable bodies (docs/deformable.md). springs = total mass [kg], stiffness [N/m],
 * damping [N s/m]; breakLimits = force [N], strain [-] (NaN or negative: never, NULL: both
 * never). fixedRegions / drivenRegions: count boxes of lo(3) hi(3) [m] each (NULL when the
 * count is 0); drivenReference [m] may be NULL (origin). attachedTo: a rigid body's name
 * whose pose drives the driven nodes ("" or NULL: the client drives them). */
DL_API int dl_declare_mass_spring_box(dl_client* client, const char* name, double interval, const char* material,
                                      const double lo[3], const double hi[3], double nodeSpacing,
                                      const double springs[3], const double breakLimits[2], int fixedCount,
                                      const double* fixedRegions, int drivenCount, const double* drivenRegions,
                                      const double drivenReference[3], const char* attachedTo, int* component);
/* mshFile is a Gmsh .msh on the SERVER; elastic = E [Pa], nu [-], rho [kg/m^3];
 * rayleigh = alpha [s], beta [1/s] (NULL: none); regions as above. */
DL_API int dl_declare_fem_mesh(dl_client* client, const char* name, double interval, const char* material,
                               const char* mshFile, const double elastic[3], const double rayleigh[2],
                               int fixedCount, const double* fixedRegions, int drivenCount,
                               const double* drivenRegions, const double drivenReference[3],
                               const char* attachedTo, int* component);

/* Orders of the typed exchange calls (see the top, "Exchange orders"). */
enum dl_exchange_order {
  DL_ORDER_SEND_FIRST = 0,       /* one call: send the inputs at t_k, return [t_k, t_k + h] (default) */
  DL_ORDER_SEND_FIRST_SPLIT = 1, /* two calls per sample: the first sends, the second returns [t_k, t_k + h] */
  DL_ORDER_RECEIVE_FIRST = 2     /* one call: return [t_k - h, t_k], then send: one interval of lag */
};
/* Sets the order of this client's typed exchange and read calls; between samples only (no
 * answer in flight: DL_ERR_STATE). The generic dl_send_package / dl_recv_package are not
 * affected: their caller orders them. */
DL_API int dl_set_exchange_order(dl_client* client, int order);

/* --- Typed exchange (in the client's order; see the top) --------------------------------
 * Counts are saturated at INT_MAX. Each returns DL_ERR_FINISHED once the simulation ended. */
/* gravity may be NULL (unchanged); out = time [s], total mass [kg], kinetic energy [J],
 * step rate [1/s]. */
DL_API int dl_simulation_box_exchange(dl_client* client, int component, const double gravity[3], double out[4],
                                      int* particleCount);
/* pose = x y z qw qx qy qz, twist = vx vy vz wx wy wz; wrenchOut = mean force(3),
 * mean torque(3), force(3), torque(3) at the interval's end [N, N m]. */
DL_API int dl_rigid_body_exchange(dl_client* client, int component, const double pose[7], const double twist[6],
                                  double wrenchOut[12]);
/* out = mass [kg], centre of mass(3) [m], mean velocity(3) [m/s]. */
DL_API int dl_region_sensor_read(dl_client* client, int component, int* count, double out[7]);
/* As dl_region_sensor_read (one exchange), and bonds = intact, broken parallel bonds whose
 * midpoint is inside. */
DL_API int dl_region_sensor_read_bonds(dl_client* client, int component, int* count, double out[7], int bonds[2]);
/* positive interval, negative interval, positive total, negative total. */
DL_API int dl_flow_sensor_read(dl_client* client, int component, int counts[4], double masses[4]);
/* interval, total, shortfall total. */
DL_API int dl_particle_source_read(dl_client* client, int component, int counts[3], double masses[3]);
/* interval, total. */
DL_API int dl_particle_sink_read(dl_client* client, int component, int counts[2], double masses[2]);
/* Deformable body (mass-spring or FEM). pose = x y z qw qx qy qz of the driving reference
 * point, twist = vx vy vz wx wy wz (pose NULL: none sent, the driven nodes keep their last
 * pose; twist NULL: zero). reactionsOut = driven force(3), driven torque(3), fixed force(3),
 * fixed torque(3) [N, N m]; displacements: 3 * capacity reals of the reported nodes [m]
 * (may be NULL when capacity is 0); *count = nodes reported; *broken = broken springs
 * (saturated at INT_MAX). */
DL_API int dl_deformable_body_exchange(dl_client* client, int component, const double pose[7],
                                       const double twist[6], double reactionsOut[12], int capacity,
                                       double* displacements, int* count, int* broken);
/* --- Run-time inputs (one-shot: sent with the component's NEXT package, i.e. by the next
 * dl_<kind>_read or dl_send_package; the server applies them from that package's step on).
 * Call them BEFORE the read of sample k to change the component from sample k on. */
/* Region sensor: each NULL (radius: NaN) is unchanged. centre [m] and orientation w x y z
 * in the frame it was declared in (world, or the attached body's); size = box side lengths
 * [m] (box only), radius [m] (sphere only). */
DL_API int dl_region_sensor_set_region(dl_client* client, int component, const double centre[3],
                                       const double orientation[4], const double size[3], double radius);
/* Simulation box: the frame's motion from the next package on (as frame in
 * dl_declare_simulation_box_ex; origin may be NULL: (0, 0, 0)). */
DL_API int dl_simulation_box_set_frame(dl_client* client, int component, const double linearAcceleration[3],
                                       const double angularVelocity[3], const double angularAcceleration[3],
                                       const double origin[3]);
/* Particle source: on = 0 stops inserting, 1 resumes; rate in the declared unit (particles/s
 * or kg/s), >= 0. The request accumulated so far is kept (no burst when switched on). */
DL_API int dl_particle_source_set_enabled(dl_client* client, int component, int on);
DL_API int dl_particle_source_set_rate(dl_client* client, int component, double rate);
/* Particle sink: on = 0 removes nothing, 1 resumes; move: new centre [m]. */
DL_API int dl_particle_sink_set_enabled(dl_client* client, int component, int on);
DL_API int dl_particle_sink_move(dl_client* client, int component, const double centre[3]);

/* positions: 3 * capacity reals, radii: capacity reals; *count = particles listed (at most
 * capacity are copied). */
DL_API int dl_particle_view_read(dl_client* client, int component, int capacity, double* positions,
                                 double* radii, int* count);
/* As dl_particle_view_read, plus velocities: 3 * capacity reals [m/s], and the particles'
 * stable ids (capacity values); either may be NULL. The listed particles are those whose id
 * is a multiple of the view's stride, in increasing id order: the same particles from
 * sample to sample whatever the engine's storage order. */
DL_API int dl_particle_view_read_ex(dl_client* client, int component, int capacity, double* positions,
                                    double* velocities, double* radii, uint64_t* ids, int* count);

#ifdef __cplusplus
}
#endif

#endif /* DEMLINK_DEMLINK_C_H */
