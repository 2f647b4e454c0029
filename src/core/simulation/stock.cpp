#include "art2part/simulation/stock.h"

namespace art2part {

double Stock::volume() const {
  double sum = 0;
  for (int axis = 0; axis < 3; ++axis) {
    double length = 0;
    for (const SpanList& spans : dexels[axis]) length += totalLength(spans);
    sum += length * lattice.cellArea(axis);
  }
  return sum / 3.0;
}

Stock boxStock(const DexelLattice& lattice) {
  Stock stock;
  stock.lattice = lattice;
  for (int axis = 0; axis < 3; ++axis)
    stock.dexels[axis].assign(lattice.rayCount(axis), SpanList{Span{lattice.box.min[axis], lattice.box.max[axis]}});
  return stock;
}

Stock meshStock(const MeshDexels& solid) {
  Stock stock;
  stock.lattice = solid.lattice();
  for (int axis = 0; axis < 3; ++axis) {
    stock.dexels[axis].resize(stock.lattice.rayCount(axis));
    for (int ray = 0; ray < stock.lattice.rayCount(axis); ++ray) stock.dexels[axis][ray] = solid.spans(axis, ray);
  }
  return stock;
}

void addSolid(Stock& stock, const MeshDexels& solid) {
  for (int axis = 0; axis < 3; ++axis)
    for (int ray = 0; ray < stock.lattice.rayCount(axis); ++ray)
      for (const SolidSpan* s = solid.begin(axis, ray); s != solid.end(axis, ray); ++s)
        addSpan(stock.dexels[axis][ray], {s->lo, s->hi});
}

Box stockBox(const Box& part_box, double margin) {
  Box box = part_box;
  box.min -= Vec3::Constant(margin);
  box.max += Vec3::Constant(margin);
  return box;
}

}  // namespace art2part
