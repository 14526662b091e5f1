// The upper block of tests/scenes/slave_fold.prm: (0.2, 0.8)² × (0.5, 1), unstructured tetrahedra
// of size 0.15. Physical surface 5 is the bottom together with the side x = 0.8, so the slave
// surface folds by 90° along the edge between them; 6 is the top. Regenerate with Debian 12's
// gmsh 4.8.4:
//   gmsh -3 -format msh22 slave_fold_upper.geo -o slave_fold_upper.msh
SetFactory("OpenCASCADE");
Box(1) = {0.2, 0.2, 0.5, 0.6, 0.6, 0.5};
Mesh.CharacteristicLengthMin = 0.15;
Mesh.CharacteristicLengthMax = 0.15;
Physical Surface(5) = {5, 2};
Physical Surface(6) = {6};
Physical Volume(1) = {1};
