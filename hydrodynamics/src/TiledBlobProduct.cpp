#include "internal/TiledBlobProduct.h"
#include "internal/TargetClones.h"
#include "internal/RotnePragerBlake.h"
#include "internal/RotnePragerYamakawa.h"
#include "TiledBlobPairs.h"
#include <algorithm>
#include <cmath>
#include <cstring>

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::TiledBlobLanes;
using OpenMM::Vec3;
using std::vector;

namespace {


/** Rows summed together over one tile: their partial sums stay in L1 while the tile is read. */
const int RowBlock = 32;

/**
 * sums (3 per row, from begin's) += the pairs of the rows [begin, end) with the sources
 * [sourceBegin, sourceEnd) (whole lanes), each row on its own: each block of rows against every
 * tile of the sources in turn. A row's own blob among the sources adds its image only.
 */
template <class Real> LANES_INLINE void addRows(const Blobs<Real>& b, int begin, int end, int sourceBegin, int sourceEnd, double* sums) {
    typename Lanes<Real>::Mask masks[TiledBlobProduct::Tile/Lanes<Real>::Count];
    for (int first = begin; first < end; first += RowBlock) {
        const int last = std::min(end, first+RowBlock);
        for (int tile = sourceBegin; tile < sourceEnd; tile += TiledBlobProduct::Tile) {
            const int tileEnd = std::min(sourceEnd, tile+TiledBlobProduct::Tile);
            for (int i = first; i < last; i++) {
                double* sum = sums+3*(i-begin);
                if (addPairsApart(b, i, tile, tileEnd, masks, sum))
                    addPairsLeftOut(b, i, tile, tileEnd, masks, sum);
                if (b.wall)
                    addImagePairs(b, i, tile, tileEnd, sum);
            }
        }
    }
}

/**
 * The pairs of two disjoint tiles of at most TiledBlobProduct::Tile blobs, [rowBegin, rowEnd) and
 * [columnBegin, columnEnd), each pair once: rowSums (3 per blob of the first) += their part of the
 * first's rows, columnSums of the second's. Each block of rows sums its columns' part in the lanes'
 * precision, then adds it to columnSums.
 */
template <class Real, bool Wall> LANES_INLINE void addTilePair(const Blobs<Real>& b, int rowBegin, int rowEnd, int columnBegin, int columnEnd,
                                                               double* rowSums, double* columnSums) {
    typename Lanes<Real>::Mask masks[TiledBlobProduct::Tile/Lanes<Real>::Count];
    Real columns[3][TiledBlobProduct::Tile];
    Real* column[3] = {columns[0], columns[1], columns[2]};
    const int width = columnEnd-columnBegin;
    for (int first = rowBegin; first < std::min(rowEnd, b.count); first += RowBlock) {
        const int last = std::min(std::min(rowEnd, b.count), first+RowBlock);
        for (int k = 0; k < 3; k++)
            std::fill(column[k], column[k]+width, (Real) 0);
        for (int i = first; i < last; i++)
            if (addPairsBothWays<Real, Wall>(b, i, columnBegin, columnEnd, masks, rowSums+3*(i-rowBegin), column))
                addPairsLeftOut(b, i, columnBegin, columnEnd, masks, rowSums+3*(i-rowBegin), columnSums);
        for (int j = 0; j < width; j++)
            for (int k = 0; k < 3; k++)
                columnSums[3*j+k] += column[k][j];
    }
}

template <class Real> LANES_INLINE void addTilePair(const Blobs<Real>& b, int rowBegin, int rowEnd, int columnBegin, int columnEnd, double* rowSums,
                                                    double* columnSums) {
    if (b.wall)
        addTilePair<Real, true>(b, rowBegin, rowEnd, columnBegin, columnEnd, rowSums, columnSums);
    else
        addTilePair<Real, false>(b, rowBegin, rowEnd, columnBegin, columnEnd, rowSums, columnSums);
}

RIGIDLANGEVIN_CLONES void addRowsInDouble(const Blobs<double>& b, int begin, int end, int sourceBegin, int sourceEnd, double* sums) {
    addRows(b, begin, end, sourceBegin, sourceEnd, sums);
}

RIGIDLANGEVIN_CLONES void addRowsInSingle(const Blobs<float>& b, int begin, int end, int sourceBegin, int sourceEnd, double* sums) {
    addRows(b, begin, end, sourceBegin, sourceEnd, sums);
}

RIGIDLANGEVIN_CLONES void addTilePairInDouble(const Blobs<double>& b, int rowBegin, int rowEnd, int columnBegin, int columnEnd, double* rowSums,
                                                    double* columnSums) {
    addTilePair(b, rowBegin, rowEnd, columnBegin, columnEnd, rowSums, columnSums);
}

RIGIDLANGEVIN_CLONES void addTilePairInSingle(const Blobs<float>& b, int rowBegin, int rowEnd, int columnBegin, int columnEnd, double* rowSums,
                                                    double* columnSums) {
    addTilePair(b, rowBegin, rowEnd, columnBegin, columnEnd, rowSums, columnSums);
}

} // namespace

double TiledBlobProduct::powerOfTwoAbove(const double* values, int count) {
    double largest = 0;
    for (int i = 0; i < count; i++)
        largest = std::max(largest, std::abs(values[i]));
    if (!(largest > 0) || !std::isfinite(largest))
        return 1;
    int exponent;
    std::frexp(largest, &exponent);
    return std::ldexp(1.0, exponent);
}

bool TiledBlobProduct::radiiFitSinglePrecision(const double* radii, int count) {
    if (count == 0)
        return true;
    const auto span = std::minmax_element(radii, radii+count);
    return *span.first*MaxSingleRadiusRatio >= *span.second;
}

void TiledBlobProduct::setBlobs(const vector<Vec3>& positions, const vector<double>& radii) {
    wall = false;
    store(positions, radii);
    damping.assign(numBlobs, 1.0);
}

void TiledBlobProduct::setBlobsAboveWall(const vector<Vec3>& positions, const vector<double>& radii, double wallZ) {
    // M~ = B M(h~) B (RotnePragerBlake.h): z holds the evaluated heights h~, damping B's diagonal.
    vector<Vec3> raised(positions);
    damping.resize(positions.size());
    for (int i = 0; i < (int) positions.size(); i++) {
        const double h = positions[i][2]-wallZ;
        raised[i][2] = RotnePragerBlake::evaluatedHeight(h, radii[i]);
        damping[i] = RotnePragerBlake::damping(h, radii[i]);
    }
    wall = true;
    store(raised, radii);
}

void TiledBlobProduct::setSinglePrecision(bool single) {
    if (single != singleRequested) {
        singleRequested = single;
        fillSingleArrays();
    }
}

void TiledBlobProduct::store(const vector<Vec3>& positions, const vector<double>& radii) {
    numBlobs = positions.size();
    const int padded = (numBlobs+Padding-1)/Padding*Padding;
    // Lengths in units of a power of two near the largest radius (exactly), so that single
    // precision's range holds every pair term; M scales as 1/length.
    lengthScale = powerOfTwoAbove(radii.data(), numBlobs);
    // Padding: far from everything and from the wall (its lanes then add zero force times finite
    // numbers), radius one.
    for (vector<double>* v : {&x, &y, &z, &fx, &fy, &fz})
        v->assign(padded, 0.0);
    radius.assign(padded, 1.0);
    radius2.assign(padded, 1.0);
    for (int i = 0; i < padded; i++) {
        const Vec3 p = (i < numBlobs ? positions[i]/lengthScale : Vec3(1e9, 1e9, 1e9));
        x[i] = p[0];
        y[i] = p[1];
        z[i] = p[2];
        if (i < numBlobs) {
            radius[i] = radii[i]/lengthScale;
            radius2[i] = radius[i]*radius[i];
        }
    }
    fillSingleArrays();
}

void TiledBlobProduct::fillSingleArrays() {
    single = singleRequested && radiiFitSinglePrecision(radius.data(), numBlobs);
    for (auto copy : {std::make_pair(&radius, &singleRadius), std::make_pair(&radius2, &singleRadius2), std::make_pair(&z, &singleHeight)}) {
        copy.second->assign(single ? copy.first->size() : 0, 0.0f);
        for (int i = 0; i < (int) copy.second->size(); i++)
            (*copy.second)[i] = (float) (*copy.first)[i];
    }
    for (vector<float>* v : {&singleFx, &singleFy, &singleFz})
        v->assign(single ? x.size() : 0, 0.0f);
    const vector<double>* exact[3] = {&x, &y, &z};
    for (int axis = 0; axis < 3; axis++) {
        singleHigh[axis].resize(single ? x.size() : 0);
        singleLow[axis].resize(single ? x.size() : 0);
        for (int i = 0; i < (int) singleHigh[axis].size(); i++) {
            singleHigh[axis][i] = (float) (*exact[axis])[i];
            singleLow[axis][i] = (float) ((*exact[axis])[i]-singleHigh[axis][i]);
        }
    }
}

void TiledBlobProduct::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out, const KrylovSolvers::ParallelFor& parallel) {
    // Forces in units of a power of two near the largest (exactly), for single precision's range.
    const double forceScale = powerOfTwoAbove(f.data(), 3*numBlobs), toForces = 1/forceScale;
    for (int i = 0; i < numBlobs; i++) {
        fx[i] = toForces*damping[i]*f[3*i];
        fy[i] = toForces*damping[i]*f[3*i+1];
        fz[i] = toForces*damping[i]*f[3*i+2];
    }
    for (int i = 0; i < (single ? numBlobs : 0); i++) {
        singleFx[i] = (float) fx[i];
        singleFy[i] = (float) fy[i];
        singleFz[i] = (float) fz[i];
    }
    out.resize(3*numBlobs);
    const int tile = pairTileSize(x.size());
    if (tile > 0)
        multiplyByTilePairs(tile, out, parallel);
    else
        parallel(numBlobs, [&] (int begin, int end) {
            std::fill(out.data()+3*begin, out.data()+3*end, 0.0);
            addRowSums(begin, end, 0, x.size(), out.data()+3*begin);
        });
    const double toVelocities = forceScale/lengthScale;
    parallel(numBlobs, [&] (int begin, int end) {
        for (int i = begin; i < end; i++) {
            const double self = RotnePragerYamakawa::selfMobility(radius[i]);
            out[3*i] = toVelocities*damping[i]*(self*fx[i]+out[3*i]);
            out[3*i+1] = toVelocities*damping[i]*(self*fy[i]+out[3*i+1]);
            out[3*i+2] = toVelocities*damping[i]*(self*fz[i]+out[3*i+2]);
        }
    });
}

int TiledBlobProduct::pairTileSize(int padded) {
    // About 16 tiles, so that two to eight threads share their pairs evenly; at most MaxPairTile
    // blobs, so that a task's two tiles and its columns' sums stay in L1.
    const int size = std::min(MaxPairTile, std::max(64, (padded/16+Padding-1)/Padding*Padding));
    return ((padded+size-1)/size <= MaxPairTiles ? size : 0);
}

TiledBlobLanes::Blobs<double> TiledBlobProduct::inDouble() const {
    return {x.data(), y.data(), z.data(), radius.data(), radius2.data(), z.data(), fx.data(), fy.data(), fz.data(),
            radius.data(), fx.data(), fy.data(), fz.data(), numBlobs, (int) x.size(), wall, {}, {}};
}

TiledBlobLanes::Blobs<float> TiledBlobProduct::inSingle() const {
    return {x.data(), y.data(), z.data(), singleRadius.data(), singleRadius2.data(), singleHeight.data(), singleFx.data(), singleFy.data(),
            singleFz.data(), radius.data(), fx.data(), fy.data(), fz.data(), numBlobs, (int) x.size(), wall,
            {singleHigh[0].data(), singleHigh[1].data(), singleHigh[2].data()}, {singleLow[0].data(), singleLow[1].data(), singleLow[2].data()}};
}

void TiledBlobProduct::addRowSums(int begin, int end, int sourceBegin, int sourceEnd, double* sums) const {
    if (single)
        addRowsInSingle(inSingle(), begin, end, sourceBegin, sourceEnd, sums);
    else
        addRowsInDouble(inDouble(), begin, end, sourceBegin, sourceEnd, sums);
}

void TiledBlobProduct::addTilePairSums(int rowBegin, int rowEnd, int columnBegin, int columnEnd, double* rowSums, double* columnSums) const {
    if (single)
        addTilePairInSingle(inSingle(), rowBegin, rowEnd, columnBegin, columnEnd, rowSums, columnSums);
    else
        addTilePairInDouble(inDouble(), rowBegin, rowEnd, columnBegin, columnEnd, rowSums, columnSums);
}

void TiledBlobProduct::multiplyByTilePairs(int tile, Eigen::VectorXd& out, const KrylovSolvers::ParallelFor& parallel) {
    // Task (I, J), I <= J, evaluates the pairs of tiles I and J (once each where I < J) into a slot
    // of its own: 3 sums per blob of I, then 3 per blob of J. Each blob's sum over the slots is then
    // taken in one order, so the product does not depend on how the tasks are shared out.
    const int padded = x.size(), numTiles = (padded+tile-1)/tile, slotSize = 6*tile;
    std::vector<std::pair<int, int>> tasks;
    for (int first = 0; first < numTiles; first++)
        for (int second = first; second < numTiles; second++)
            tasks.push_back({first, second});
    tileSums.resize(tasks.size()*slotSize);
    parallel(tasks.size(), [&] (int begin, int end) {
        for (int t = begin; t < end; t++) {
            double* slot = tileSums.data()+(size_t) t*slotSize;
            std::fill(slot, slot+slotSize, 0.0);
            const int rows = tasks[t].first*tile, columns = tasks[t].second*tile;
            if (rows == columns)
                addRowSums(rows, std::min(numBlobs, rows+tile), rows, std::min(padded, rows+tile), slot);
            else
                addTilePairSums(rows, rows+tile, columns, std::min(padded, columns+tile), slot, slot+3*tile);
        }
    });
    auto slotOf = [&] (int first, int second) { return (size_t) (first*numTiles-first*(first-1)/2+(second-first))*slotSize; };
    parallel(numTiles, [&] (int begin, int end) {
        for (int tileOfRow = begin; tileOfRow < end; tileOfRow++)
            for (int i = tileOfRow*tile; i < std::min(numBlobs, (tileOfRow+1)*tile); i++)
                for (int k = 0; k < 3; k++) {
                    double sum = 0;
                    for (int other = 0; other < numTiles; other++)
                        sum += (tileOfRow <= other ? tileSums[slotOf(tileOfRow, other)+3*(i-tileOfRow*tile)+k]
                                                   : tileSums[slotOf(other, tileOfRow)+3*tile+3*(i-tileOfRow*tile)+k]);
                    out[3*i+k] = sum;
                }
    });
}
