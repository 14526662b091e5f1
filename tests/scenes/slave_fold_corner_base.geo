// The base of tests/scenes/slave_fold_corner.prm: the box (0, 1)² × (0, 0.5) with a wall
// (0.85, 1) × (0, 1) × (0.5, 0.8) on it, unstructured tetrahedra of size 0.13. Physical surface 7
// is the master surface: the top of the box left of the wall and the wall's face x = 0.85, which
// faces the side x = 0.8 of the block 5 cm away; 1 is the bottom. Regenerate with Debian 12's
// gmsh 4.8.4:
//   gmsh -3 -format msh22 slave_fold_corner_base.geo -o slave_fold_corner_base.msh
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 0.5};
Box(2) = {0.85, 0, 0.5, 0.15, 1, 0.3};
BooleanUnion{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Mesh.CharacteristicLengthMin = 0.13;
Mesh.CharacteristicLengthMax = 0.13;
top[] = Surface In BoundingBox{-0.01, -0.01, 0.49, 0.86, 1.01, 0.51};
wall[] = Surface In BoundingBox{0.84, -0.01, 0.49, 0.86, 1.01, 0.81};
Physical Surface(7) = {top[], wall[]};
Physical Surface(1) = Surface In BoundingBox{-0.01, -0.01, -0.01, 1.01, 1.01, 0.01};
Physical Volume(1) = {1};
