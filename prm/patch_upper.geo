// The upper block of prm/patch_test_unstructured.prm: (0, 1) × (0, 1) × (0.5, 1),
// unstructured tetrahedra of size 0.19. Boundary parts are chosen by plane predicates in the
// parameter file, so only the volume is tagged. Regenerate with Debian 12's gmsh 4.8.4:
//   gmsh -3 -format msh22 patch_upper.geo -o patch_upper.msh
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0.5, 1, 1, 0.5};
Mesh.CharacteristicLengthMin = 0.19;
Mesh.CharacteristicLengthMax = 0.19;
Physical Volume(1) = {1};
