/* scene_keys.c: every scene key, with unit, default, accepted values and
 * meaning (see scene_keys.h). A default here must be the value the reader
 * uses when the key is absent: tests/cli/test_scene_keys.c sets each one
 * and checks nothing changes. */
#include "api/scene_keys.h"

#define BOOL "boolean"

const ini_key scene_keys_rod[] = {
    {"rod", "length", "m", "required", "> 0", "L, the rod's length"},
    {"rod", "diameter", "m", "required", "> 0, < length",
     "d; EI with I = pi d^4/64, GJ with J = pi d^4/32"},
    {"rod", "density", "kg/m^3", "required", "> 0", "rho"},
    {"rod", "youngs_modulus", "Pa", "required", "> 0", "E"},
    {"rod", "shear_modulus", "Pa", "required", "> 0", "G"},
    {"rod", "nodes", "-", "required", "3 .. 100001", "NS, nodes along the rod; ds = L/(NS-1)"},
    {"rod", "refine", "m m -", "-", "S0 S1 FACTOR[, ...], 1 < FACTOR <= 100, up to 8",
     "a graded grid: segments between arc lengths S0 and S1 FACTOR times shorter, NS kept "
     "(implicit scheme; self-contact, surfaces rigid or tissue, elastic pads, instruments, "
     "punctures, the needle's holes, cuts, shape, settle, other rods, video)"},
    {"rod", "rotary_inertia_scale", "-", "1", "> 0",
     "multiplies rho I and rho J (the thesis scheme needs about 1e7)"},
    {"rod", "origin", "m", "0 0 0", "3 numbers",
     "global: the root (node 0) at t = 0; with a shape file, its first point"},
    {"rod", "direction", "-", "1 0 0", "3 numbers, not all 0",
     "initial tangent of a straight rod (normalised); d1, d2 turn from y, z by the smallest "
     "rotation taking x to it"},
    {"rod", "shape", "-", "straight", "straight | FILE.csv",
     "FILE.csv: the starting centreline, header x,y,z (m, global), its length = `length` "
     "(1e-6 relative); nodes placed along it exactly ds apart; frames twist-free along it"},
    {"rod", "curvature", "1/m", "0 0 0", "3 numbers",
     "intrinsic Darboux vector u0, director components: M = B (u - u0) (a spool's curl)"},
    {"rod", "initial_velocity", "m/s", "0 0 0", "3 numbers", "global, every node at t = 0"},
    {"rod", "self_contact", "-", "yes", "yes | no",
     "strands touch at the diameter, never pass (implicit scheme); no: they pass through"},
    {"rod", "friction", "-", "0.2", ">= 0", "Coulomb coefficient between strands that touch"},
    {"rod", "settle", "s", "0", ">= 0, at most 100000 steps",
     "before t = 0 the thread moves this long from its starting shape, ends held, the tip's "
     "loads as at t = 0, its velocities zeroed whenever its kinetic energy falls; it starts at "
     "rest there (a drawn knot's snap spent before the run; one rod, implicit, no punctures, "
     "pad, instruments or cuts)"},

    {"solver", "scheme", "-", "implicit", "thesis | implicit | static",
     "how the rod is stepped"},
    {"solver", "dt", "s", "auto", "auto, or > 0",
     "auto: half the scheme's stable limit, at most 1/20 of the first bending period"},
    {"solver", "duration", "s", "10", "> 0", "simulated time"},
    {"solver", "theta", "-", "1", "0.5 .. 1 | backward_euler | crank_nicolson",
     "implicit: 1 backward Euler (damps), 0.5 Crank-Nicolson"},
    {"solver", "newton_tolerance", "-", "1e-8", "> 0, < 1",
     "implicit and static schemes: relative residual that ends Newton"},
    {"solver", "newton_max_iterations", "-", "25", "1 .. 1000", "implicit and static schemes"},
    {"solver", "exact_rotation", "-", "true", BOOL,
     "thesis scheme: true the exact exponential map, false (4.6) as printed"},

    {"tip", "frame", "-", "director", "director | global",
     "director: on the tip's d1 d2 d3, turning with it (follower); global: x y z (dead)"},
    {"tip", "force", "N", "0 0 0", "3 numbers", "tip force, on `frame`"},
    {"tip", "moment", "N m", "0 0 0", "3 numbers", "tip moment, on `frame` (M3 twists)"},
    {"tip", "profile", "s", "step",
     "step | ramp T | pulse T_on T_off | impulse T | table FILE.csv",
     "full from t = 0; rising over T; on for T_on <= t < T_off; +load for T, then -load "
     "for T; a load table"},

    {"loads", "gravity", "m/s^2", "0 0 0", "3 numbers", "global; adds rho A g per length"},
    {"loads", "distributed_force", "N/m", "0 0 0", "3 numbers", "global, per length"},
    {"loads", "linear_damping", "N s/m^2", "0", ">= 0", "force per length -c v"},
    {"loads", "angular_damping", "N m s/m", "0", ">= 0", "moment per length -c omega"},
    {"loads", "distributed_moment", "N m/m", "0 0 0", "3 numbers", "global, per length"},

    {"point_load", "s", "m", "required", "0 .. length",
     "arc length of the load ([point_load] repeats); it acts at the nearest node"},
    {"point_load", "force", "N", "0 0 0", "3 numbers", "global (dead), times the [tip] profile"},
    {"point_load", "moment", "N m", "0 0 0", "3 numbers", "global (dead), times the [tip] profile"},
    {"point_load", "rod", "-", "-", "a [rod NAME]'s NAME",
     "several rods: the rod it loads (required with several rods, refused with a bare [rod])"},

    {"ends", "root", "-", "clamped", "clamped | pinned | free",
     "clamped: position and frame held; pinned: position held, twist about d3 held, free to "
     "bend; free: nothing held"},
    {"ends", "tip", "-", "free", "free | pinned | clamped",
     "a held tip stays where it starts, unless tip_motion or tip_slide says otherwise"},
    {"ends", "root_motion", "-", "-", "FILE.csv",
     "the held root follows a path: header t,x,y,z or t,x,y,z,rx,ry,rz (m; rotation vector "
     "from the starting frame, rad); first row = where the root starts; C2 between rows, at "
     "rest at the first and after the last"},
    {"ends", "tip_motion", "-", "-", "FILE.csv", "the same for the held tip (the needle holder)"},
    {"ends", "root_slide", "-", "0 0 0", "3 numbers",
     "direction along which the held root slides freely; 0 0 0: held in place; with "
     "root_motion a sleeve that moves (and turns) with the path (implicit scheme)"},
    {"ends", "tip_slide", "-", "0 0 0", "3 numbers",
     "the same for the tip; 1 0 0: the sleeve of Euler's and Greenhill's columns"},
    {"ends", "root_twist", "-", "free", "free | held",
     "a clamped root on a slide: free turns about the slide (a sleeve), held does not (a "
     "carriage; with a turning root_motion the sleeve turns the end; implicit scheme)"},
    {"ends", "tip_twist", "-", "free", "free | held",
     "the same for a clamped tip on a slide: held is the twisted-rod experiment's carriage "
     "under tension"},
    {"ends", "needle", "m", "0", ">= 0",
     "radius of a curved needle drawn with its back at the tip; 0: none (no mechanics)"},

    /* obstacles */
    {"surface", "shape", "-", "plane", "plane | box | cylinder | sphere | mesh",
     "a rigid obstacle ([surface] repeats); the rod touches it at its radius (implicit scheme)"},
    {"surface", "center", "m", "0 0 0", "3 numbers",
     "a point of the plane; the box's centre; a point on the cylinder's axis; the sphere's centre; mesh: added to the file's coordinates"},
    {"surface", "normal", "-", "0 0 1", "3 numbers, not all 0",
     "plane: outward normal; cylinder: axis (the cylinder is unbounded along it)"},
    {"surface", "size", "m", "-", "box: 3 numbers > 0; cylinder, sphere: 1 number > 0",
     "box: edge lengths along x y z (axis-aligned); cylinder, sphere: radius; plane: none"},
    {"surface", "friction", "-", "0.3", ">= 0", "Coulomb coefficient between rod and surface"},
    {"surface", "tissue", "-", "no", BOOL,
     "yes: the needle (driven tip) passing through makes punctures"},
    {"surface", "track_spacing", "m", "0", ">= 0; tissue only",
     "> 0: the needle's path inside the tissue leaves punctures this far apart along the "
     "thread (at least 2 node spacings; each a point of the tissue, frictional as the holes; "
     "made one node spacing behind the needle's back; none once 3 of the run's 16 punctures "
     "remain), so the thread lies in the needle's track, under a wound it bit below; 0: "
     "only the holes where it enters and leaves (the thread a straight chord between)"},
    {"surface", "rounding", "m", "0", ">= 0, below half the shortest edge; box only",
     "the radius a box's edges and corners are rounded to (a skin pad's, a table's); an elastic pad's deformed surface has its convex edges rounded to it where the thread touches"},
    {"surface", "file", "-", "-", "FILE.stl (ASCII or binary); mesh only, required",
     "the mesh's triangles (m), outward side counter-clockwise; solid behind the closest face, edge or vertex (a sheet is solid behind its front)"},
    {"surface", "max_triangles", "-", "200000", "1 .. 5000000",
     "mesh: the most triangles its file may hold (a larger file is refused before it is read)"},
    {"surface", "model", "-", "rigid", "rigid | elastic",
     "elastic (a box with tissue = yes): the pad deforms, a finite-element neo-Hookean solid "
     "meshed from the box, quasi-static, each puncture a point of it that moves with it and "
     "carries the thread's force; the rod lies on its deformed surface (the wound's slit "
     "open), pressing it where it touches; it starts at rest, settled before t = 0 under its "
     "pretension, held faces and weight"},
    {"surface", "youngs_modulus", "Pa", "500000", "> 0",
     "elastic pad: E (skin 1e5..1e6)"},
    {"surface", "poisson_ratio", "-", "0.45", "-1 < nu < 0.5", "elastic pad: nu"},
    {"surface", "density", "kg/m^3", "1100", "> 0", "elastic pad: its weight under gravity"},
    {"surface", "damping", "s", "0.01", ">= 0",
     "elastic pad: stiffness-proportional damping (the quasi-static pad does not use it)"},
    {"surface", "element_size", "m", "0.003", "> 0, <= the box's shortest edge",
     "elastic pad: the tets' size away from the wound"},
    {"surface", "element_order", "-", "1", "1 | 2",
     "elastic pad: 1 linear tets, 2 quadratic (right at twice the size; ~2x the cost)"},
    {"surface", "wound_refine", "-", "0.333", "(0, 1]",
     "elastic pad: the tets' size at the wound / element_size"},
    {"surface", "wound_tip_refine", "-", "1", "(0, 1]",
     "elastic pad: the tets' size at the slit's bottom edge and across its plane / that at the "
     "wound, growing 1.3 per layer away (a crack front: 0.25 with element_order 2 makes the "
     "gap converge)"},
    {"surface", "max_nodes", "-", "20000", ">= 1",
     "elastic pad: the mesh budget; a finer mesh is refused before it is made"},
    {"surface", "held", "-", "bottom", "bottom | bottom sides | none",
     "elastic pad: the faces held (stretched by the pretension, then fixed)"},
    {"surface", "pretension", "-", "0 0 0", "3 strains in (-0.5, 0.5)",
     "elastic pad: the skin's own tension, a strain along x y z at the held faces: opens a wound"},
    {"surface", "wound", "m", "-", "x0 y0 x1 y1 depth",
     "elastic pad: a slit in the top face along x or y, ends inside the top face (an end on its "
     "edge cuts the slit through to that face), 0 < depth < the box's height"},
    {"puncture", "point", "m", "required", "3 numbers, on the starting shape",
     "a point the thread passes through, sliding ([puncture] repeats, at most 16); on a tissue surface, pairs in order: the thread between is inside; on an elastic pad, on its skin as settled at t = 0"},
    {"puncture", "friction", "-", "0.2", ">= 0",
     "Coulomb coefficient along the thread in the puncture"},
    {"puncture", "rod", "-", "-", "a [rod NAME]'s NAME",
     "several rods: the rod whose thread passes through it (required with several rods, "
     "refused with a bare [rod], whose punctures are its own); an elastic pad is one for all "
     "rods, each rod's punctures loading it and moving with it"},

    {"instrument", "kind", "-", "required", "needle_holder | forceps | scissors",
     "a rigid surgical instrument driven along its path ([instrument] repeats, at most 4): "
     "jaws, shanks and a needle holder's box lock (across the hinge, drawn as it touches) "
     "as capsules the thread touches with friction"},
    {"instrument", "name", "-", "-", "a word, unique",
     "names it in the summary's grasps, in messages and in --set instrument.NAME.key=value; "
     "absent: its kind"},
    {"instrument", "path", "-", "required", "FILE.csv",
     "header t,x,y,z,rx,ry,rz,jaw: the jaws' tip (m, global), its rotation vector (rad; local "
     "x along the shafts to the tip, z the jaws' opening plane) and the jaws' opening (0 "
     "closed .. 1 open), interpolated smoothly; jaws closing below 0.1 grasp the thread "
     "between them, opening release it; scissors' blades closing below 0.1 cut it where it "
     "crosses them (the piece on the side no fixed end or puncture holds leaves the run, "
     "with its grasps and driven end); "
     "instruments pass through surfaces: a path taking a jaw, shank or box lock more than "
     "its radius into a [surface] (sampled every 1 ms) is a warning naming the part, the time "
     "and the depth; the jaws deeper than max_depth into a rigid [surface]: refused"},
    {"instrument", "max_depth", "m", "-", "> 0",
     "the deepest the path may take the jaws into a rigid [surface] (deeper: the run is "
     "refused, exit 2); absent: the jaws' thickness, 2 jaw radii"},
    {"instrument", "may_overlap", "-", "no", "yes | no",
     "instruments do not collide with each other (both are driven): paths taking a jaw, "
     "shank or box lock into another instrument's (sampled every 1 ms) are refused, exit 2, "
     "naming both, the parts, the time and the depth; jaws may graze jaws by the thinner "
     "jaw's radius (a needle handed over), other parts touch by a tenth of the thinner's "
     "radius; yes in either of two instruments: allowed, they run through each other (the "
     "summary's min_instrument_gap, below 0, tells how deep)"},
    {"instrument", "size", "m", "0.14", "> 0",
     "overall length; jaws and shanks scale with it (a 0.14 m needle holder: 15 mm jaws)"},
    {"instrument", "friction", "-", "0.3", ">= 0",
     "Coulomb coefficient of the thread on the instrument"},
    {"instrument", "grip", "N", "5", "> 0",
     "the force along the thread beyond which it slides through closed jaws"},
    {"instrument", "rod", "-", "-", "the NAME of a [rod NAME] (a bare [rod]: rod)",
     "the only rod its jaws take (scissors: cut); absent: the rod nearest their middle when "
     "they close (all rods touch every instrument); the summary's grasps and cuts name the rod; "
     "with needle = yes and several rods required: the rod whose tip the needle is on (the "
     "other rods touch the holder, never held by it)"},
    {"instrument", "needle", "-", "no", "yes | no",
     "needle_holder: holds the needle (ends.needle) at its jaws' tip: its path drives the "
     "thread's tip (ends.tip = clamped); with ends.tip_motion given too, that is the needle's "
     "path whole (a rodsim live record, its handovers in it) and the holder's path moves its "
     "jaws only; its jaws touch and take no thread until a [needle_grasp] has handed the "
     "needle to other jaws and they have opened and closed again (its shanks and box lock "
     "touch it)"},
    {"needle_grasp", "t", "s", "required", "increasing, after the holder's path starts",
     "the needle handed over ([needle_grasp] repeats, at most 8; the summary's needle_grasps): "
     "from t it stays as it was at t in the named jaws, which must be within a jaw length of "
     "it then; before the first, the needle = yes holder holds it; rodsim live hands it to "
     "the jaws its lines drive the same way"},
    {"needle_grasp", "instrument", "-", "required", "an [instrument]'s name, not scissors",
     "whose jaws take the needle: jaws holding it touch no thread; jaws a grasp names take "
     "none before it (they close on the needle) but touch it; jaws that have handed the "
     "needle on are ordinary jaws (touch the thread, closing on it takes it) from their first "
     "close after they have opened, so that they let go of the needle's back first"},
    {"cut", "t", "s", "required", "> 0",
     "the thread is cut at this time, without scissors ([cut] repeats, at most 8; the summary's "
     "cuts): the piece from the cut to the end on the side no fixed end (no path) or puncture "
     "holds leaves the run, its grasps and driven end letting go (neither side anchored: the "
     "side no grasp or path holds, then the shorter; both: refused, a warning)"},
    {"cut", "s", "m", "required", "0 < s < rod.length",
     "where: arc length on the uncut thread from its root, cut at the nearest node"},
    {"cut", "rod", "-", "-", "a [rod NAME]'s NAME",
     "several rods: the rod it cuts (required with several rods, refused with a bare [rod]); "
     "s is on that rod"},

    {"physics", "twist", "-", "on", BOOL, "off: twist quasi-static (no torsion waves)"},
    {"physics", "rotary_inertia", "-", "on", BOOL, "off: no rotary inertia (implicit scheme)"},
    {"physics", "gravity", "-", "on", BOOL, "off: [loads] gravity and distributed_force ignored"},
    {"physics", "damping", "-", "on", BOOL, "off: [loads] damping ignored"},
    {"physics", "planar", "-", "on", BOOL,
     "on: loads in the x-y plane are solved as a planar problem (implicit; exact, faster)"},

    {"render", "fps", "1/s", "30", "1 .. 1000",
     "video frames per second"},
    {"render", "width", "px", "1280", "even, 16 .. 7680", "video width"},
    {"render", "height", "px", "720", "even, 16 .. 4320", "video height"},
    {"render", "crf", "-", "18", "0 .. 51", "H.264 quality: 0 lossless, lower is better"},
    {"render", "preset", "-", "veryfast",
     "ultrafast .. veryslow", "x264 speed preset (veryfast: superfast's motion search)"},
    {"render", "samples", "-", "4", "0 .. 16",
     "multisample antialiasing (the backdrop's, with antialias fxaa), 0 = off"},
    {"render", "antialias", "-", "fxaa", "fxaa | msaa",
     "fxaa: one sample per pixel, then FXAA over what the frame drew (faster; the backdrop "
     "multisampled); msaa: `samples` per pixel; samples = 0: neither"},
    {"render", "visual_radius", "m", "auto", "auto, or > 0",
     "radius drawn; auto: 1 % of the length, never below the true radius; the true "
     "radius when strands touched (self-contact)"},
    {"render", "sides", "-", "24", "6 .. 128", "facets around the tube"},
    {"render", "needle_arc", "-", "3/8", "3/8 | 1/2", "arc of the needle drawn at the tip ([ends] needle > 0)"},
    {"render", "stripe", "-", "director", "director | formula | off",
     "the amber material line that shows twist; formula: thesis (4.17) literally"},
    {"render", "arrows", "-", "true", BOOL, "tip force (red) and moment (green) arrows"},
    {"render", "grid", "-", "true", BOOL, "backdrop grid and scale bar"},
    {"render", "overlay", "-", "true", BOOL, "text: scene, time, scheme, nodes, loads"},
    {"render", "overlay_solver", "-", "true", BOOL,
     "the time line names the scheme and the nodes; false: the time alone"},
    {"render", "poster", "-", "true", BOOL, "write SCENE.png, the last frame"},
    {"render", "frames_png", "-", "false", BOOL, "also write SCENE_frames/NNNNN.png"},
    {"render", "camera", "-", "perspective", "perspective | orthographic", "projection"},
    {"render", "view", "-", "0.3 -0.45 1", "3 numbers, not all 0",
     "direction from the rod to the eye"},
    {"render", "background", "-", "f6f7f9", "rrggbb, \"#rrggbb\", or 3 numbers in 0..1",
     "background colour"},
    /* what a viewer needs */
    {"render", "title", "-", "-", "text",
     "overlay title; absent: the scene's own words, the first sentence of the comment that "
     "opens the file (at most 72 characters, cut at a clause), else the file's name"},
    {"render", "caption", "-", "-", "text", "a line under the title"},
    {"render", "hide", "-", "none",
     "none, or of: title caption time ends legend loads scale triad gravity colorbar",
     "overlay items not drawn"},
    {"render", "color", "-", "solid", "solid | curvature | twist | tension | speed",
     "tube colour by curvature, twist u3 (1/m), tension N . d3 (N) or speed (m/s), with a colour bar"},
    {"render", "rod_color", "-", "2e66c7", "as background", "tube colour when solid"},
    {"render", "colormap", "-", "viridis", "viridis | cividis", "colour map"},
    {"render", "color_range", "-", "auto", "auto, or lo hi", "colour bar range; auto: the run's"},
    {"render", "speed", "-", "1", "> 0",
     "simulated s per video s (0.25: 4x slow motion); output fps/speed per simulated s"},
    {"render", "magnify", "-", "1", ">= 1", "motion from the first frame drawn x this"},
    /* obstacles and depth */
    {"render", "smooth", "-", "true", BOOL,
     "the tube drawn through a smooth curve between the nodes (each node's tangent d3 kept, "
     "frames turned evenly), a segment cut by its turn; false: straight from node to node"},
    {"render", "shadows", "-", "true", BOOL,
     "the rod, needle and glyphs cast shadows from the key light on the surfaces and ground"},
    {"render", "ground", "-", "auto", "auto | yes | no",
     "a ground plane just below the run's lowest point, across the load's direction; auto: "
     "when gravity acts, no plane surface exists and the camera looks from above"},
    {"render", "wound", "m", "-", "6 numbers x1 y1 z1 x2 y2 z2",
     "global: a wound line drawn on the surfaces as a dark red incision; absent: none"},
    {"render", "cutaway", "-", "no", "no | yes | x0 y0 z0 nx ny nz",
     "the tissue drawn cut open, as a stitch is drawn in section: the tissue surfaces (rigid "
     "or elastic) on the normal's side of the plane are not drawn, their cut face is (dermis "
     "and subcutis), the thread and needle inside are seen whole; yes: the plane through the "
     "stitch's punctures, across the wound, facing the eye; x0 y0 z0 (m, global) a point of "
     "it, nx ny nz its normal, towards the side not drawn"},
    /* knots */
    {"render", "knot", "-", "auto", "auto | yes | no",
     "the knot type of the centreline, per frame, top right (e.g. knot: trefoil (3_1)); "
     "auto: when a frame of the run is knotted"},
    /* a camera that follows, views side by side */
    {"render", "framing", "-", "run", "run | follow | knot",
     "run: one camera frames the whole run; follow: the rod's current bounds centred and "
     "filling the picture, smoothed over 0.25 video s (a fall or a drift followed without "
     "lag), never clipped; knot: the same around the knotted part (strands within 3 "
     "diameters), the tails cut"},
    {"render", "views", "-", "-", "1 to 3 of: perspective orthographic top front side",
     "the frame split into side-by-side views, each labelled with its axes and scale bar; "
     "top, front, side: orthographic along -z, +y, -x; absent: camera and view"},
    /* a camera for a course: where it looks, from where, and in which time ranges */
    {"render", "look_at", "m", "-", "3 numbers",
     "global: the point at the picture's centre, for the whole run (a [shot] may change it)"},
    {"render", "follow", "-", "none", "none | knot",
     "knot: the picture centred on the knotted part (strands within 3 diameters), smoothed "
     "over 0.25 video s; with distance, its scale held (the knot seen to tighten)"},
    {"render", "distance", "m", "-", "> 0",
     "eye to the point looked at: the picture is 2 distance tan(fov/2) high there (orthographic "
     "too); absent: the framing's scale"},
    {"render", "fov", "deg", "30", "1 .. 120", "perspective's vertical field of view"},
    {"render", "azimuth", "deg", "-", "-360 .. 360",
     "view direction from +x towards +y (with elevation; replaces view; the other from view)"},
    {"render", "elevation", "deg", "-", "-90 .. 90", "view direction above the x-y plane"},
    {"render", "eye", "m", "-", "3 numbers",
     "global: where the eye stands (direction and distance to the point looked at); not with "
     "azimuth or elevation"},
    {"render", "slow_motion", "s s -", "none",
     "none; auto [FACTOR]; or triples T0 T1 FACTOR, 0 <= T0 < T1, 1 < FACTOR <= 1000",
     "frames FACTOR times closer in simulated time within T0 .. T1 (moved to the nearest "
     "frames), so that range plays FACTOR times slower; the overlay says so while it is on; "
     "steps stay within solver.dt; e.g. 1.2 1.8 4, 3 3.5 2; auto: around the knot's fastest "
     "tightening (the rope in it, as the summary measures it, falling at least half as fast), "
     "found by a first pass of the run, FACTOR 4 unless given"},
    {"shot", "from", "s", "required", ">= 0",
     "a time range with its own camera ([shot] repeats, at most 16, not overlapping): "
     "its start; outside every shot the [render] camera"},
    {"shot", "to", "s", "required", "> from", "its end, included unless the next shot starts there"},
    {"shot", "ease", "s", "-", "0 .. to - from",
     "absent or 0: a cut; else the camera moves from the one before over this time (smoothstep)"},
    {"shot", "look_at", "m", "-", "3 numbers", "as [render] look_at, for this shot; absent: [render]'s (each shot key)"},
    {"shot", "follow", "-", "-", "none | knot", "as [render] follow"},
    {"shot", "distance", "m", "-", "> 0", "as [render] distance"},
    {"shot", "fov", "deg", "-", "1 .. 120", "as [render] fov"},
    {"shot", "azimuth", "deg", "-", "-360 .. 360",
     "as [render] azimuth (the other angle from the [render] view)"},
    {"shot", "elevation", "deg", "-", "-90 .. 90", "as [render] elevation"},
    {"shot", "eye", "m", "-", "3 numbers", "as [render] eye"},
    {"shot", "caption", "-", "-", "text",
     "the caption line while the shot lasts, over [render] caption (absent: [render]'s)"},
    {NULL, NULL, NULL, NULL, NULL, NULL},
};

const ini_key scene_keys_beam[] = {
    {"material", "youngs_modulus", "Pa", "required", "1 .. 1e13", "E"},
    {"material", "radius", "m", "-", "1e-9 .. 1e3",
     "solid circular section: A = pi r^2, I = pi r^4/4 (or give area and second_moment)"},
    {"material", "area", "m^2", "-", "1e-18 .. 1e6", "A, with second_moment instead of radius"},
    {"material", "second_moment", "m^4", "-", "1e-40 .. 1e14", "I, with area instead of radius"},

    {"geometry", "length", "m", "-", "1e-6 .. 1e6", "a generated rod of this length (or give nodes)"},
    {"geometry", "angle", "deg", "0", "-360 .. 360", "direction at node 1, above the +x axis"},
    {"geometry", "curvature_radius", "m", "0", "0, or |R| >= length/(2 pi)",
     "0 straight; R > 0 an arc turning anticlockwise, R < 0 clockwise"},
    {"geometry", "elements", "-", "4", "1 .. 5000", "elements of the generated rod"},
    {"geometry", "nodes", "m", "-", "x1 z1, x2 z2, ... (2 .. 5001, |x|, |z| <= 1e6)",
     "explicit node positions instead of length .. elements"},

    {"support", "node", "-", "required", "1 .. nodes", "the supported node ([support] repeats)"},
    {"support", "type", "-", "required", "clamped | pinned | roller",
     "clamped holds u w theta; pinned u w; roller w"},

    {"load", "node", "-", "required", "1 .. nodes", "the loaded node ([load] repeats)"},
    {"load", "force", "N", "0 0", "2 numbers, each |F| <= 1e12", "Fx Fz, global (z up)"},
    {"load", "moment", "N m", "0", "|M| <= 1e12", "anticlockwise positive"},

    {"plot", "width", "px", "1200", "64 .. 8192", "figure width"},
    {"plot", "height", "px", "800", "64 .. 8192", "figure height"},
    {"plot", "scale", "-", "auto", "auto, or > 0",
     "deformation drawn x scale; auto: the largest displacement about 15 % of the structure"},
    {"plot", "title", "-", "-", "text, < 256 characters", "figure title; absent: FEM: SCENE"},
    {NULL, NULL, NULL, NULL, NULL, NULL},
};

/* A table cell: '|' escaped so that it does not end the cell. */
static void cell(FILE *f, const char *text)
{
    for (const char *c = text; *c; c++) {
        if (*c == '|') fputc('\\', f);
        fputc(*c, f);
    }
}

void scene_keys_print_markdown(FILE *f, const ini_key *table)
{
    if (table == scene_keys_beam)
        fprintf(f, "A beam scene (`rodsim fem`): the same syntax; `[support]` and `[load]` "
                   "repeat (`--set` changes the first); nodes count from 1.\n\n");
    else
        fprintf(f, "A rod scene (`rodsim run`): `[section]`, `key = value`, `#` comments, SI "
                   "units, numbers without a unit (`length = 50 cm` is an error that says "
                   "`write 0.5 (m)`); vectors: numbers separated by blanks or commas; "
                   "booleans: true false yes no on off 1 0. A bad key or value is an error naming `file:line` (exit "
                   "2). Variants: a `[variant NAME]` section holds `section.key = value` lines, "
                   "applied in order by `--set variant=NAME` (later `--set`s override them); "
                   "without it they are not read (`instrument_tie_square.ini`: the granny's "
                   "two paths).\n\n"
                   "Several rods: `[rod NAME]`, `[ends NAME]`, `[tip NAME]` for each rod (up to "
                   "8; a bare `[rod]` is a scene's single rod, named `rod`) hold the keys of "
                   "`[rod]`, `[ends]`, `[tip]` below; the other sections are shared. The rods "
                   "take one implicit step together, with one dt, coupled only through contact: "
                   "the strands' contact law (friction: the mean of the two rods' "
                   "`rod.friction`), each force acting on both rods, equal and opposite, within "
                   "the step, whatever the order of the sections; rods apart cost what each "
                   "costs alone. Drawn in the order's colours "
                   "(`render.rod_color` first). Not with several rods: the thesis and static "
                   "schemes. Each `[puncture]`, `[point_load]` and `[cut]` names its rod "
                   "(`puncture.rod`, `point_load.rod`, `cut.rod`); scissors cut the rod nearest "
                   "their blades, a needle holder holding the needle names its rod "
                   "(`instrument.rod`); a tissue surface, rigid or an elastic pad, is one for "
                   "all rods. `--set \"rod NAME.key=V\"` sets a key of one rod.\n\n");
    fprintf(f, "| key | unit | default | accepted | meaning |\n| --- | --- | --- | --- | --- |\n");
    for (const ini_key *k = table; k->section; k++) {
        fprintf(f, "| `%s.%s` | ", k->section, k->key);
        cell(f, k->unit);
        fprintf(f, " | ");
        cell(f, k->fallback);
        fprintf(f, " | ");
        cell(f, k->accepted);
        fprintf(f, " | ");
        cell(f, k->meaning);
        fprintf(f, " |\n");
    }
}
