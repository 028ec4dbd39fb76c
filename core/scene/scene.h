// The scene: objects (geometry with their own BVH, object.h), instances (object + transform + material),
// materials, lights, textures and background. commit() rebuilds only what changed: the BVH of each edited object,
// and the small top-level BVH over instances when any instance or object bound changed. It also detects which
// features the scene can use so the integrator can run a kernel that skips the rest.
// Where each part lives: registry and commit in scene.cpp, the background SAH upgrade in upgrade.cpp, the
// two-level traversal (closest hit with its tie-break, shadow transmittance, surface data at a hit) in
// traversal.cpp, the environment lookup in environment.cpp, light and material sanitising in light.cpp /
// material.cpp; each shape's code is in geometry/shape_*.cpp.
#pragma once

#include "accel/bvh.h"
#include "scene/environment.h"
#include "scene/light.h"
#include "scene/material.h"
#include "scene/object.h"
#include "geometry/shapes.h"
#include "geometry/volume.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace whitted {

/// What the committed scene contains; the integrator leaves out every mechanism whose flag is false (transforms
/// is for callers: the benchmark's POV-Ray export).
struct Features {
  bool reflective = false;    ///< Some visible material has kr > 0.
  bool transmissive = false;  ///< Some visible material has kt > 0.
  bool shadowLights = false;  ///< Some light casts shadows.
  bool transforms = false;    ///< Some visible instance has a non-identity transform.
  bool textures = false;      ///< Some visible material uses a texture with texture coordinates present.
  bool edges = false;         ///< Some visible material draws edges (Material::edgeWidth > 0).
  bool volumes = false;       ///< Some visible volume can be traced (Scene::addVolume).
};

/// Counts of what commit() did, for statistics and for tests of caching.
struct CommitStats {
  int objectsRebuilt = 0;  ///< Per-object BVHs built in this commit.
  /// Of those, built with the fast (Morton) builder: objects whose geometry was replaced after it had been built
  /// once (time steps, new contour values), where a geometry change is likely to come again and build time,
  /// not the last percent of trace speed, decides the frame. First builds use the SAH builder.
  int objectsFastBuilt = 0;
  /// Objects whose points moved on unchanged connectivity (a deforming mesh's time step): BVH boxes refit
  /// bottom-up, no rebuild (not counted in objectsRebuilt).
  int objectsRefit = 0;
  /// Objects refit in this commit whose tree then traced too slowly by the SAH (cost above
  /// Object::kRefitRebuildRatio times its cost when built): rebuilt with the fast builder instead (counted in
  /// objectsRebuilt and objectsFastBuilt, not in objectsRefit).
  int objectsRefitRejected = 0;
  /// Largest SAH cost ratio (refitted tree / tree when built) over the objects refit in this commit; 0 if none.
  double refitCostRatio = 0.0;
  /// Objects whose fast tree was replaced in this commit by the SAH tree a background build finished (see
  /// Scene::setBackgroundUpgrade; counted in no other field).
  int objectsUpgraded = 0;
  /// This commit waited for a background build (its kUpgradeWaitCommits-th commit; see setBackgroundUpgrade).
  bool waitedForUpgrade = false;
  /// This commit stopped a background build kept at idle priority and started it again at normal priority,
  /// because the process may not raise a thread's priority (see Scene::setBackgroundUpgrade).
  bool upgradeRestarted = false;
  bool topLevelRebuilt = false;
  double secondsBuild = 0.0;          ///< Wall time of all BVH builds in this commit.
  std::size_t invalidPrimitives = 0;  ///< Primitives skipped (non-finite or degenerate) in rebuilt objects.
  std::size_t invalidMaterials = 0;   ///< Materials with values clamped by sanitizeMaterial.
  std::size_t invalidLights = 0;      ///< Lights with non-finite or negative values (clamped or switched off).
  /// Volumes prepared in this commit that cannot be traced (skipped; Scene::volumeError says why).
  std::size_t invalidVolumes = 0;
  std::size_t invalidVoxels = 0;  ///< Non-finite scalars in volumes prepared in this commit (traced as transparent).
};

/// Totals over the scene, for the frame report.
struct SceneStats {
  std::size_t triangles = 0, spheres = 0, tubes = 0, objects = 0, instances = 0;
  std::size_t tracedInstances = 0;  ///< Visible instances in the top-level BVH (instances counts hidden ones too).
  std::size_t bvhNodes = 0, bvhBytes = 0, geometryBytes = 0;
  /// Objects traced with a fast (Morton) tree: with the background upgrade, those whose SAH tree is not in yet.
  std::size_t fastTrees = 0;
  std::size_t textures = 0;      ///< Textures holding texels (colour maps included).
  std::size_t textureBytes = 0;  ///< Memory of their texels, bytes (allocated capacity).
  std::size_t volumes = 0;       ///< Volumes traced.
  std::size_t volumeBytes = 0;   ///< Memory of their scalars, bytes.
};

class Scene {
 public:
  Scene();
  ~Scene();  ///< Waits for a running background build.
  /// Moves wait for the background builds of both scenes first (a running one reads its scene's objects).
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;

  // Objects -----------------------------------------------------------------------------------------------
  /// Adds geometry; returns its object id. The data is taken by value (move it in).
  uint32_t addMesh(TriangleMesh mesh);
  uint32_t addSpheres(SphereSet spheres);
  uint32_t addTubes(TubeSet tubes);
  /// Replaces an object's geometry (marks it for rebuild at the next commit).
  void setMesh(uint32_t object, TriangleMesh mesh);
  void setSpheres(uint32_t object, SphereSet spheres);
  void setTubes(uint32_t object, TubeSet tubes);
  /// Replaces an object's data like setMesh / setSpheres / setTubes, but keeps its BVH when the geometry is
  /// bit-for-bit the one it was built from (triangles: positions and triangles; spheres: centres and radii;
  /// tubes: end points and radii), so attribute-only edits (colours, colour-map coordinates and map, normals,
  /// texture coordinates) rebuild nothing. Returns true if the geometry changed (rebuilt at the next commit).
  /// Cost: one comparison of the geometry arrays.
  bool updateMesh(uint32_t object, TriangleMesh mesh);
  bool updateSpheres(uint32_t object, SphereSet spheres);
  bool updateTubes(uint32_t object, TubeSet tubes);
  /// Frees an object's data; instances of it become invisible.
  void removeObject(uint32_t object);
  /// The builder for geometry replaced after its first build: BvhBuildQuality::Fast (the default: time steps and
  /// edited geometry rebuild in about half the SAH build's time, for a tree that traces somewhat slower) or Sah.
  /// New geometry always gets the SAH build.
  void setReplacedBuildQuality(BvhBuildQuality quality) { replacedQuality_ = quality; }
  /// Background upgrade (default off): commit() builds new and replaced geometry of at least kUpgradeMin
  /// primitives with the fast builder, whatever setReplacedBuildQuality says, so the frame that shows it waits for
  /// the shortest build; startUpgrades(), called once that frame is traced, builds the SAH tree of every such
  /// object on a background thread (one build thread at idle scheduling priority: it uses only cores nothing
  /// else wants); the first commit() after it finished swaps the SAH trees in (CommitStats::objectsUpgraded). Until
  /// the swap, frames trace the complete fast tree. When frames come back to back, no core is idle: from the
  /// (kUpgradeIdleCommits + 1)-th commit after startUpgrades on, the build runs at normal priority (sharing the
  /// cores with the frames), and the kUpgradeWaitCommits-th commit waits for it, so an upgrade never stays pending
  /// for ever. Where the process may not raise a thread's priority (Linux without CAP_SYS_NICE: an ordinary user),
  /// the first of those commits stops the idle build and starts it again at normal priority instead (frames back
  /// to back left the idle build almost no time, so little work is lost; CommitStats::upgradeRestarted). Traversal
  /// is exact with either tree: images do not change.
  void setBackgroundUpgrade(bool on) { backgroundUpgrade_ = on; }
  bool backgroundUpgrade() const { return backgroundUpgrade_; }
  /// Objects smaller than this get the SAH build at once (it takes a few milliseconds) with the background upgrade.
  static constexpr std::size_t kUpgradeMin = 50000;
  /// Commits during which a background build keeps idle priority. Three: the three frames after the fast one are
  /// as fast as without an upgrade (the total of the first four frames stays below the SAH-first one's), and the
  /// 1M-triangle SAH build (about 0.6 s of one core) then costs the next two frames about 0.3 s in all.
  static constexpr int kUpgradeIdleCommits = 3;
  /// The commit (counted from startUpgrades) that waits for a background build still running.
  static constexpr int kUpgradeWaitCommits = 16;
  /// Starts the background SAH build of the objects traced with a fast tree, unless one is running or the upgrade
  /// is off. Call it after the frame (the build then uses the time between frames, not the frame's cores).
  void startUpgrades();
  /// Waits until the running background build (if any) has finished; the next commit() swaps it in.
  void waitForUpgrades();
  /// A background build is running or finished and not swapped in yet.
  bool upgradePending() const { return upgrade_.job != nullptr; }
  /// A background build has finished; the next commit() swaps it in.
  bool upgradeFinished() const;
  /// For tests: called on the background thread once its trees are built, before it reports them finished; with
  /// a hook the build keeps normal priority (a test polling for it on a busy machine would starve an idle one).
  void setUpgradeHookForTesting(std::function<void()> hook) { upgradeHook_ = std::move(hook); }
  /// For tests: background builds behave as where the process may not raise a thread's priority (they are
  /// lowered, and raising them fails), whatever this process may do.
  void setUpgradeRaiseDeniedForTesting(bool deny) { upgradeRaiseDenied_ = deny; }
  /// The object as it stands (geometry in leaf order once committed, BVH, leaf order), e.g. to keep a copy.
  const Object& object(uint32_t object) const { return objects_[object]; }
  /// Moves an object out of the scene whole (geometry, BVH, leaf order: a committed one stays committed), leaving
  /// its id without geometry (as removeObject does) so the id can take other geometry; restoreObject puts it back.
  /// For time caches: an earlier time step's object kept outside the scene costs no tracing and no statistics.
  Object takeObject(uint32_t object);
  /// Puts an object (taken by takeObject, or a copy of object()) at id, replacing what is there. A committed
  /// object keeps its BVH: nothing is rebuilt; only the top level is (its bounds may differ).
  void restoreObject(uint32_t object, Object o);
  std::size_t objectCount() const { return objects_.size(); }
  GeometryType objectType(uint32_t object) const { return objects_[object].type(); }
  /// A copy of an object's geometry as given (triangles in their original order; empty if of another shape).
  TriangleMesh mesh(uint32_t object) const { return objects_[object].originalGeometry<TriangleMesh>(); }
  SphereSet spheres(uint32_t object) const { return objects_[object].originalGeometry<SphereSet>(); }
  TubeSet tubes(uint32_t object) const { return objects_[object].originalGeometry<TubeSet>(); }

  // Instances ---------------------------------------------------------------------------------------------
  /// Places an object in the world with an object -> world affine transform and a material.
  uint32_t addInstance(uint32_t object, const Mat4& toWorld, uint32_t material);
  void setInstanceTransform(uint32_t instance, const Mat4& toWorld);
  void setInstanceMaterial(uint32_t instance, uint32_t material);
  void setInstanceVisible(uint32_t instance, bool visible);
  void setInstanceObject(uint32_t instance, uint32_t object);
  /// Gives every surface point of the instance the geometry colour c (RGBA in [0,1]), in place of its object's own
  /// vertex / primitive colours; the material's colorSource decides, as for those, whether it replaces the ambient
  /// and / or diffuse colour and multiplies the opacity. For many instances of one object with one colour each
  /// (glyphs): one material for all of them, and 16 bytes per instance instead of a material per colour.
  /// Default: none (the object's colours).
  void setInstanceColor(uint32_t instance, const Color4& c);
  /// Removes the instance colour (back to the object's colours).
  void clearInstanceColor(uint32_t instance);
  std::size_t instanceCount() const { return instances_.size(); }
  uint32_t instanceObject(uint32_t instance) const { return instances_[instance].object; }
  /// Removes all instances (objects stay, so their BVHs are kept).
  void clearInstances();

  // Materials, textures, lights, background ---------------------------------------------------------------
  uint32_t addMaterial(const Material& m);
  Material& material(uint32_t id) { return materials_[id]; }
  const Material& material(uint32_t id) const { return materials_[id]; }
  std::size_t materialCount() const { return materials_.size(); }
  void clearMaterials() { materials_.clear(); }
  /// Adds a texture; returns its id, reusing the id of a removed texture when there is one.
  uint32_t addTexture(Texture t);
  /// Replaces texture `id` in place: materials and meshes referring to it see the new texels from the next
  /// frame on; nothing is rebuilt.
  void setTexture(uint32_t id, Texture t);
  /// Frees texture `id`'s texels (id must not be removed already); a later addTexture may return the id again.
  /// Until then anything still referring to it samples white (an empty texture).
  void removeTexture(uint32_t id);
  const Texture& texture(uint32_t id) const { return textures_[id]; }
  /// Texture slots, removed ones included (ids are below this).
  std::size_t textureCount() const { return textures_.size(); }
  void clearTextures() {
    textures_.clear();
    freeTextures_.clear();
  }
  std::vector<Light>& lights() { return lights_; }
  const std::vector<Light>& lights() const { return lights_; }

  Color background{0.0f};   ///< Background colour (bottom colour when gradient). Default black.
  Color background2{0.0f};  ///< Top colour of a vertical gradient background.
  bool gradientBackground = false;
  float backgroundAlpha = 1.0f;  ///< Alpha written for misses (0 for layered or parallel compositing).
  /// Environment image for directional escapes (see EnvironmentMap). Default none.
  EnvironmentMap environmentMap;
  /// What a reflected or bent ray leaving the scene in direction d sees: the environment image when there is
  /// one (and its textures exist), else the background colour, or for a gradient background the mix of bottom
  /// and top colours by elevation 0.5 (1 + d.up) along the camera's view-up.
  Color environment(const Vec3& d, const Vec3& up) const;

  // Volumes (scene/volumes.cpp) ----------------------------------------------------------------------------
  /// Adds a volume (grid, transfer function, interpolation, step) in world coordinates; returns its id. Prepared at
  /// the next commit; one that cannot be traced is skipped with a reason (volumeError) and counted
  /// (CommitStats::invalidVolumes). Volumes are kept beside the objects, not in the surfaces' top-level BVH: a ray
  /// clips every traced volume's box (few per scene).
  uint32_t addVolume(Volume v);
  void setVolume(uint32_t id, Volume v);
  /// Replaces a volume's transfer function only (a colour-map edit): the grid stays as converted.
  void setVolumeTransfer(uint32_t id, const TransferFunction& tf);
  void setVolumeVisible(uint32_t id, bool visible);
  void removeVolume(uint32_t id);
  /// How shaded volumes (TransferFunction::shade) are lit by the lights (VolumeLighting; read at commit): the
  /// ambient light colour (default 1) and whether the lights arrive along the viewing rays (default off).
  Color volumeAmbient{1.0f};
  bool volumeLightsAlongRays = false;
  std::size_t volumeCount() const { return volumes_.size(); }
  const Volume& volume(uint32_t id) const { return volumes_[id].volume; }
  /// Moves volume id's scalars out (its grid is left empty, and the volume is skipped until setVolume replaces it):
  /// a caller converting a new grid of the same size (the next step of a time series) can write into memory that
  /// is already mapped instead of allocating and zeroing the grid again.
  VolumeScalars releaseVolumeScalars(uint32_t id);
  /// Why volume id is not traced (empty if it is, or before the commit that prepares it).
  const std::string& volumeError(uint32_t id) const { return volumes_[id].error; }
  /// Emission-absorption along ray over (ray.tMin, tEnd) through every traced volume, front to back into acc (see
  /// Volume::march; volumes are marched one after the other in the order they are entered, so overlapping volumes
  /// are composited approximately). Stops once acc.transmittance < stopBelow. stepScale: Volume::march's;
  /// coarser: each volume at twice the step it marches at with stepScale (the step estimate's march: a volume
  /// already at its finest step, Volume::finestStepScale, is compared with twice that, not with itself).
  void marchVolumes(const Ray& ray, double tEnd, bool emission, float stopBelow, VolumeMarch& acc, int stepScale = 0,
                    bool coarser = false) const;
  /// The least Volume::finestStepScale of the traced volumes (0 without any): how many times progressive
  /// refinement can halve a step and still change some volume's march.
  int finestVolumeStepScale() const;

  // Commit and queries ------------------------------------------------------------------------------------
  /// Rebuilds dirty object BVHs and, if needed, the top-level BVH; detects features. Sanitises materials, lights
  /// and background in place (non-finite values replaced, ranges clamped) so no input can produce a NaN pixel.
  CommitStats commit();
  const Features& features() const { return features_; }
  SceneStats stats() const;
  /// World bounds of visible instances (valid after commit).
  Bounds3 bounds() const { return bounds_; }

  /// Closest hit along ray in (tMin, tMax); among hits at the same distance (within 1e-10 relative) the lowest
  /// (instance, primitive) wins. nodes, if given, counts visited BVH nodes.
  bool intersect(const Ray& ray, Hit& hit, uint64_t* nodes = nullptr) const;
  /// Closest-hit packet: the rays rays[i] of the bit mask active (at most four, e.g. camera rays of neighbouring
  /// pixels) walk the BVHs together; hits[i] is exactly intersect(rays[i], hits[i])'s hit, and bit i of the result
  /// its return value. nodes, if given, counts visited BVH nodes once per packet.
  unsigned intersectPacket(const Ray* rays, unsigned active, Hit* hits, uint64_t* nodes = nullptr) const;

  /// Transmittance along a shadow ray over (tMin, tMax): zero if an opaque surface blocks it, otherwise the
  /// product of kt of every transmissive surface crossed. A surface crossed once attenuates once: a crossing that
  /// several primitives of one object report (a ray exactly through an edge or vertex shared by triangles, or
  /// through the joint of two tubes) counts once; boundary hits of one object closer than the sum of their
  /// rounding-error bounds (PrimHit::tError) are that one crossing. Stops early once below cutoff (returns zero;
  /// *cutByThreshold, if given, is then set: every channel of the true transmittance is below cutoff).
  /// Volumes on the ray multiply it by their transmittance, marched at step.scale (Volume::march's stepScale);
  /// step.error, if given, gets the step truncation's estimate of the result (largest channel): the volumes
  /// marched again at twice the step, the two transmittances' difference times the surfaces' product.
  Color transmittance(const Ray& ray, float cutoff, uint64_t* nodes = nullptr, bool* cutByThreshold = nullptr,
                      VolumeStep step = VolumeStep()) const;

  /// Shadow packet: the rays rays[i] of the bit mask active (at most four, e.g. the shadow rays of four camera
  /// hits toward one light) walk the BVHs together. Sets bit i of blocked when an opaque surface blocks ray i;
  /// returns the mask of rays whose answer must come from transmittance() (they met a transmissive instance, or
  /// the scene has transmissive surfaces and the ray was blocked: see there). Every other active ray has
  /// transmittance() = 0 when blocked and 1 when not, bit for bit. nodes, if given, counts visited BVH nodes once
  /// per packet.
  unsigned occludedPacket(const Ray* rays, unsigned active, unsigned& blocked, uint64_t* nodes = nullptr) const;

  /// Surface data of a hit.
  SurfacePoint surface(const Ray& ray, const Hit& hit) const;
  /// False when no ray inside frustum f can hit anything: every leaf box of the top level, and of the objects of
  /// identity instances, lies outside f (Frustum::excludes); true otherwise (conservative: an instance with a
  /// transform counts by its world box, a scene with volumes is always true). The camera's tile culling.
  bool frustumMayHit(const Frustum& f) const;
  /// Distance, in world units across the ray, from the hit point p to the nearest drawn edge of the hit triangle
  /// (TriangleMesh::edgeFlags; see edgeDistance in edges.h); infinity for spheres and tubes.
  double edgeDistance(const Ray& ray, const Hit& hit, const Vec3& p) const;

 private:
  struct Instance {
    uint32_t object = 0;
    uint32_t material = 0;
    Mat4 toWorld{1.0}, toObject{1.0};
    Mat3 normalToWorld{1.0};
    Color4 color{1.0f};  ///< Geometry colour of every point when hasColor (setInstanceColor).
    bool hasColor = false;
    bool identity = true;
    bool visible = true;
    /// ray in object space (t keeps its meaning: the same point for the same t).
    Ray objectRay(const Ray& ray) const {
      if (identity) return ray;
      Ray r = ray;
      r.origin = transformPoint(toObject, ray.origin);
      r.dir = transformVector(toObject, ray.dir);
      return r;
    }
  };

  /// setMesh / setSpheres / setTubes and their update variants, for geometry of any shape.
  template <typename G>
  void setGeometry(uint32_t object, G&& g);
  template <typename G>
  bool updateGeometry(uint32_t object, G&& g);
  template <typename Fn>
  void forEachVisibleInstance(Fn&& fn) const;

  struct Upgrade;  ///< A background SAH build (upgrade.cpp).
  /// Its handle: moving it first waits for the builds on both sides (declared first among the members, so a
  /// moved scene's objects move only after that).
  struct UpgradeSlot {
    std::shared_ptr<Upgrade> job;
    UpgradeSlot();
    UpgradeSlot(UpgradeSlot&& o) noexcept;
    UpgradeSlot& operator=(UpgradeSlot&& o) noexcept;
    ~UpgradeSlot();
    void wait();    ///< Joins the build's thread if it runs.
    void settle();  ///< Waits until the build (if any) has read the scene.
    void drop();    ///< The build's trees are not wanted: waits for its read of the scene, then retires it.
    void retire();  ///< Cancels the build (after its read) and leaves its thread to stop on its own; job empty.
  };
  void settleUpgrade();                 ///< Before objects_ changes: waits until a running build has read it.
  /// Counts a commit for a running build: raises it, restarts it at normal priority or waits for it, in time.
  void pressUpgrade(CommitStats& st);
  void launchUpgrade(std::shared_ptr<Upgrade> job);  ///< Starts job's thread and makes it the running build.
  void adoptUpgrades(CommitStats& st);  ///< Swaps in a finished background build's trees that are still current.

  // The steps of commit(), in order
  void buildObjects(CommitStats& st);    ///< Refit or rebuild the objects that changed.
  void buildTopLevel(CommitStats& st);   ///< Tree over the visible instances' world boxes.
  void sanitizeInputs(CommitStats& st);  ///< Clamp what shading reads, so no input can produce a NaN pixel.
  void updateFeatures();                 ///< What the traced instances, their materials and the lights use.
  void prepareVolumes(CommitStats& st);  ///< Prepares changed volumes; a change rebuilds the top level (bounds_).
  void addVolumeBounds();                ///< After the top level: bounds_ takes in the traced volumes.
  void volumeStats(SceneStats& s) const;

  struct SceneVolume {
    Volume volume;
    std::string error;  ///< Why it is not traced (prepare's message).
    bool dirty = true, alive = true;
    bool traced() const { return alive && volume.visible && volume.ready(); }
  };
  std::vector<SceneVolume> volumes_;
  std::vector<VolumeLight> volumeLights_;  ///< The lights as volume shading sees them (made at commit).
  VolumeLighting volumeLighting_;  ///< Ambient and alongRays as committed (lights: volumeLights_).
  void prepareVolumeLights();

  UpgradeSlot upgrade_;  // first: see UpgradeSlot
  std::vector<Object> objects_;
  std::vector<Instance> instances_;
  std::vector<Material> materials_;
  std::vector<Texture> textures_;
  std::vector<uint32_t> freeTextures_;  ///< Ids of removed textures, reused by addTexture.
  std::vector<Light> lights_;

  Bvh top_;
  std::vector<uint32_t> topInstances_;  ///< Top-level leaf slot -> instance index.
  bool topDirty_ = true;
  BvhBuildQuality replacedQuality_ = BvhBuildQuality::Fast;
  bool backgroundUpgrade_ = false;
  uint64_t treeCounter_ = 0;  ///< Last Object::treeVersion given.
  std::function<void()> upgradeHook_;
  bool upgradeRaiseDenied_ = false;
  Features features_;
  Bounds3 bounds_;
};

}  // namespace whitted
