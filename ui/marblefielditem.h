#pragma once

#include "core/world.h"

#include <QColor>
#include <QGraphicsItem>
#include <QHash>
#include <QLineF>
#include <QList>
#include <QPixmap>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace marbles {

/// Every marble of one World drawn by a single item in a single paint() call, for scenes where
/// one QGraphicsItem per marble would be too many (thousands of marbles).
///
/// The item mirrors the world and owns no physics: it keeps a pointer to a World that must
/// outlive it (or be replaced with setWorld()), and reads positions when it paints. The owner
/// calls syncFromWorld() once per simulated frame and after every edit. Scene coordinates are
/// stage px, y down; the item sits at the scene origin.
///
/// Each marble is a pre-rendered shaded sprite (the look of MarbleItem), cached per radius on
/// screen and colour at the device's pixel ratio, so blitting it costs one drawPixmap. Marbles
/// smaller than kSmallestSpriteRadiusDevicePx on screen (kTinyRadiusDevicePx above the antialias
/// threshold) become filled squares. Style::Ghost draws the same
/// marbles as dashed, semi-transparent outlines with no fill (a second model running beside the
/// first, see CompareRun). The Figure 11.12 vectors of World::lastHit (as VectorItem draws
/// them) can be drawn in the same pass, batched per colour.
class MarbleFieldItem : public QGraphicsItem {
public:
    enum { Type = UserType + 20 };

    /// Shaded balls, or outlines of a second model's marbles.
    enum class Style { Solid, Ghost };

    /// Above this many marbles the vectors and the tiny marbles are drawn without antialiasing
    /// (sprites keep their pre-rendered smooth edges, which cost nothing at draw time; the few
    /// selection rings stay smooth).
    static constexpr int kDefaultAntialiasThreshold = 5000;
    /// Above the antialias threshold, marbles smaller than this radius on the device (px) are
    /// drawn as squares, not sprites: a large crowd fitted to the window is mostly such marbles,
    /// and a square costs far less to draw than a sprite.
    static constexpr double kTinyRadiusDevicePx = 2.0;
    /// Up to the antialias threshold, marbles get sprites down to this radius on the device (px),
    /// so that the small marbles of a crowd look like its big ones: round, shaded and outlined
    /// (squares beside them read as another kind of object). Smaller ones are squares.
    static constexpr double kSmallestSpriteRadiusDevicePx = 0.75;
    /// Sprite radii are rounded to this step, device px (at most half of it off the true size).
    static constexpr double kSpriteRadiusStepDevicePx = 0.25;
    /// The cache is emptied when it holds more sprites than this, or more bytes than
    /// kMaxSpriteCacheBytes (after many zoom levels).
    static constexpr int kMaxCachedSprites = 2048;
    static constexpr qsizetype kMaxSpriteCacheBytes = 64 * 1024 * 1024;
    /// Marbles larger than this radius on the device (px) are painted directly, not cached:
    /// zoomed that far in, few are on screen and each would need a large sprite of its own.
    static constexpr double kMaxSpriteRadiusDevicePx = 48.0;
    /// The vectors are drawn only where the book's 30 stage px come to at least this many device
    /// px: a crowd zoomed out to 1-px marbles would be buried under a tangle of arrows too short
    /// to read. Zooming in brings them back.
    static constexpr double kMinVectorDevicePx = 6.0;
    /// Up to this many marbles' vectors on screen are antialiased (below the antialias
    /// threshold). More are drawn with sharp pixels: a crowd's thousands of thin, crossing
    /// vectors read as well either way, and the raster engine draws them twice as fast
    /// (renderbench -n 2000, 1280 x 800: paint 9.5 -> 4.8 ms).
    static constexpr int kMaxSmoothVectors = 1000;

    /// A field showing `world` (may be null: the item draws nothing), which must outlive the item.
    explicit MarbleFieldItem(const World *world = nullptr, Style style = Style::Solid);
    ~MarbleFieldItem() override;

    /// The world shown (not owned), or null.
    const World *world() const { return m_world; }
    /// Shows another world (not owned; null shows nothing) and re-syncs.
    void setWorld(const World *world);
    /// Re-reads the world after frames or edits: bounds (stage and every marble), colours, then
    /// schedules a repaint if anything drawn changed. O(marbles); call once per frame, not once
    /// per marble.
    void syncFromWorld();

    /// Solid balls or ghost outlines.
    Style style() const { return m_style; }
    /// Chooses solid balls or ghost outlines.
    void setStyle(Style style);

    /// True when the Figure 11.12 vectors are drawn.
    bool vectorsVisible() const { return m_vectorsVisible; }
    /// Shows or hides the Figure 11.12 vectors (velocity before the last hit blue, collision
    /// vector both ways red, reflected velocity green), for marbles that have been hit.
    void setVectorsVisible(bool visible);
    /// True when the vectors are long enough to be drawn at `scale` (device px per stage px).
    static bool vectorsLegibleAt(double scale);

    /// The selected marbles (indices into the world), drawn with MarbleItem's dashed ring in the selection's colour.
    const QList<int> &selectedMarbles() const { return m_selected; }
    /// Sets the selected marbles; out-of-range indices are ignored when painting.
    /// (Named so as not to hide QGraphicsItem::setSelected(bool).)
    void setSelectedMarbles(const QList<int> &indices);
    /// The marble held by the mouse (solid green ring), or -1.
    int heldMarble() const { return m_held; }
    /// Sets the marble held by the mouse, or -1 for none.
    void setHeldMarble(int i);
    /// Colours for marbles that have none of their own (the plotted marbles, in their lines'
    /// colours); the others are the stage's blue.
    void setTints(const QList<QPair<int, QColor>> &tints);

    /// Marble count above which antialiasing is off.
    int antialiasThreshold() const { return m_antialiasThreshold; }
    /// Sets the marble count above which antialiasing is off.
    void setAntialiasThreshold(int marbles);
    /// True when the current world is drawn with antialiasing (its count is within the threshold).
    bool isAntialiased() const;

    /// The marble whose disc contains scene point `p` (stage px), the highest index winning as
    /// it is drawn last; -1 when none. A linear scan, as worldedit's marbleAt(): one click costs
    /// microseconds even for 20,000 marbles.
    int marbleAt(QPointF p) const;

    /// Sprites in the cache (for tests and the benchmark).
    int cachedSpriteCount() const { return static_cast<int>(m_sprites.size()); }

    /// The colour marble `i` is drawn in: its scene colour, or the chapter's blue.
    QColor marbleColor(int i) const;

    int type() const override { return Type; }
    QRectF boundingRect() const override;
    void paint(QPainter *painter, const QStyleOptionGraphicsItem *option, QWidget *widget) override;

private:
    struct SpriteKey {
        int radiusSteps = 0; ///< device radius / kSpriteRadiusStepDevicePx, rounded
        QRgb color = 0;
        int dprPercent = 100; ///< device pixel ratio * 100
        bool ghost = false;

        friend bool operator==(const SpriteKey &, const SpriteKey &) = default;
        friend size_t qHash(const SpriteKey &key, size_t seed = 0)
        {
            return qHashMulti(seed, key.radiusSteps, key.color, key.dprPercent, key.ghost);
        }
    };

    const QPixmap &sprite(const SpriteKey &key);
    /// Re-reads the colours; returns whether any changed.
    bool syncColors();
    /// Keeps a copy of the positions, radii and (while drawn) collision vectors; returns whether
    /// they differ from the last copy.
    bool keepShown();
    void paintVectors(QPainter *painter, const QTransform &toDevice, double scale, const QRectF &visible, bool antialias);
    void paintRings(QPainter *painter, const QTransform &toDevice, double scale);

    const World *m_world = nullptr;
    Style m_style = Style::Solid;
    bool m_vectorsVisible = false;
    QList<int> m_selected;
    int m_held = -1;
    int m_antialiasThreshold = kDefaultAntialiasThreshold;

    QRectF m_bounds;
    double m_maxRadius = 0.0;
    std::vector<std::string> m_colorText; ///< info[i].color as last parsed
    std::vector<QRgb> m_color;            ///< marble i's colour, opaque
    std::vector<std::pair<int, QRgb>> m_tints; ///< setTints()
    std::vector<Vec2> m_shownPosition;    ///< what the last sync saw (keepShown())
    std::vector<double> m_shownRadius;
    std::vector<HitRecord> m_shownHits;   ///< kept while the vectors are drawn
    QHash<SpriteKey, QPixmap> m_sprites;
    qsizetype m_spriteBytes = 0; ///< memory held by m_sprites

    // Per-paint buffers, kept so that their capacity survives from frame to frame.
    std::vector<std::pair<QRgb, std::vector<QRectF>>> m_tiny; ///< tiny marbles, per colour
    std::vector<QLineF> m_redLines;
    std::vector<QLineF> m_blueLines;
    std::vector<QLineF> m_greenLines;
    std::vector<QPointF> m_blueHeads;  ///< three corners per head
    std::vector<QPointF> m_greenHeads; ///< three corners per head
};

} // namespace marbles
