# The scene conversion of the VTK module: vtkRenderer -> whitted::Scene, one file pair per VTK concept (see
# plugin/README.md, "Data flow"). Listed once, for the module (module/CMakeLists.txt) and for the conversion fuzz
# target (testing/fuzz), which compiles these without the pass and the compositor (they need OpenGL).
set(whitted_conversion_sources
  vtkWhittedSceneConverter.cxx     # the prop walk: what is traced, instances, retiring what is unused
  vtkWhittedInstanceSlots.cxx      # scene instances and materials, reused across frames
  vtkWhittedActorPieces.cxx        # the polydata an actor draws (blocks, surfaces); plain points / lines
  vtkWhittedGeometryCache.cxx      # converted geometry per (mapper, input or block, options)
  vtkWhittedGeometryTimeCache.cxx  #   its time cache: earlier contents kept by fingerprint, and what is kept
  vtkWhittedGeometryFingerprint.cxx #  the fingerprints: a polydata's contents, a mapper's colouring state
  vtkWhittedPolyDataConverter.cxx  # one polydata -> triangles, spheres, tubes
  vtkWhittedPolyDataTriangles.cxx  #   polygons and strips -> triangle mesh (normals, coordinates)
  vtkWhittedPolyDataSpheres.cxx    #   vertices (or every point) -> spheres
  vtkWhittedPolyDataTubes.cxx      #   lines (and wireframe edges) -> tubes
  vtkWhittedPolyDataColors.cxx     #   the mapper's colours per point or cell
  vtkWhittedGlyphConverter.cxx     # vtkGlyph3DMapper -> one instance per glyph
  vtkWhittedGlyphPlacement.cxx     # where VTK places each glyph of a vtkGlyph3DMapper
  vtkWhittedVolumeConverter.cxx    # vtkVolume (image data, ray-cast mappers) -> scene volumes
  vtkWhittedVolumeResampled.cxx    #   an unstructured grid's volume resampled to image data
  vtkWhittedTextureCache.cxx       # vtkTexture -> scene textures
  vtkWhittedMaterialKeys.cxx       # the Whitted information keys (public header: module/CMakeLists.txt)
  vtkWhittedMaterials.cxx          # vtkProperty + Whitted keys -> material
  vtkWhittedLights.cxx             # vtkLight -> lights
  vtkWhittedEnvironment.cxx        # background, skybox, environment texture
  vtkWhittedWarnings.cxx)          # every warning, once per prop
set(whitted_conversion_headers
  vtkWhittedSceneConverter.h
  vtkWhittedInstanceSlots.h
  vtkWhittedActorPieces.h
  vtkWhittedGeometryCache.h
  vtkWhittedGeometryTimeCache.h
  vtkWhittedGeometryFingerprint.h
  vtkWhittedPolyDataConverter.h
  vtkWhittedPolyDataPrimitives.h
  vtkWhittedGlyphConverter.h
  vtkWhittedGlyphPlacement.h
  vtkWhittedVolumeConverter.h
  vtkWhittedVolumeResampled.h
  vtkWhittedTextureCache.h
  vtkWhittedMaterials.h
  vtkWhittedLights.h
  vtkWhittedEnvironment.h
  vtkWhittedWarnings.h
  vtkWhittedMatrix.h)
