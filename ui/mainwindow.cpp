#include "ui/mainwindow.h"

#include "core/presets.h"
#include "ui/autosaver.h"
#include "ui/comparerun.h"
#include "ui/elidinglabel.h"
#include "ui/elidingstatusbar.h"
#include "ui/filenames.h"
#include "ui/inspectordock.h"
#include "ui/numbertext.h"
#include "ui/parametersdock.h"
#include "ui/plotdock.h"
#include "ui/prompts.h"
#include "ui/refusingspinbox.h"
#include "ui/runcontroller.h"
#include "ui/scenedocument.h"
#include "ui/stageview.h"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QChartView>
#include <QCloseEvent>
#include <QAbstractButton>
#include <QAbstractItemView>
#include <QComboBox>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDir>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFileInfo>
#include <QFontMetrics>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QMenu>
#include <QMenuBar>
#include <QMessageBox>
#include <QResizeEvent>
#include <QScreen>
#include <QScrollArea>
#include <QSettings>
#include <QShowEvent>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QStandardItemModel>
#include <QStatusBar>
#include <QStyle>
#include <QTimer>
#include <QToolBar>
#include <QToolButton>
#include <QUndoStack>
#include <QUndoView>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace marbles {

namespace {

/// Run speeds offered in the toolbar.
constexpr double kSpeeds[] = {0.1, 0.25, 0.5, 1.0, 2.0, 4.0};
/// Index of 1x in kSpeeds.
constexpr int kRealTimeSpeedIndex = 3;

/// The desktop theme's icon, or the style's own when the theme has none (bare X servers).
QIcon themeIcon(const QString &name, QStyle::StandardPixmap fallback)
{
    return QIcon::fromTheme(name, QApplication::style()->standardIcon(fallback));
}

/// Whether `locale` writes its group separator as a space (French's narrow no-break space).
bool groupsWithSpaces(const QLocale &locale)
{
    const QString mark = locale.groupSeparator();
    return mark.size() == 1 && mark.at(0).isSpace();
}

QString keyRecentFiles()
{
    return QStringLiteral("recentFiles");
}

} // namespace

MainWindow::MainWindow(QWidget *parent)
    : QMainWindow(parent)
    , m_document(new SceneDocument(this))
    , m_prompts(std::make_unique<Prompts>())
{
    setObjectName(QStringLiteral("mainWindow"));
    qApp->installEventFilter(this); // Space for focused buttons (eventFilter())
    m_view = new StageView(m_document, this);
    m_run = new RunController(m_document, this);
    // Made before the docks: its frame slot runs before the plot's, which samples both worlds.
    m_compare = new CompareRun(m_document, this);
    m_compare->setStage(m_view->scene());

    // The central widget: a message bar (hidden until needed) above the stage.
    auto *central = new QWidget(this);
    auto *layout = new QVBoxLayout(central);
    layout->setContentsMargins(0, 0, 0, 0);
    layout->setSpacing(0);
    m_messageBar = new QWidget(central);
    m_messageBar->setObjectName(QStringLiteral("messageBar"));
    m_messageBar->setAutoFillBackground(true);
    m_messageBar->setStyleSheet(
        QStringLiteral("#messageBar { background: #fdecea; border-bottom: 1px solid #e0a8a2; } "
                       "#messageBar QLabel { color: #611a15; }"));
    auto *barLayout = new QHBoxLayout(m_messageBar);
    barLayout->setContentsMargins(10, 6, 6, 6);
    m_messageText = new QLabel(m_messageBar);
    m_messageText->setWordWrap(true);
    barLayout->addWidget(m_messageText, 1);
    auto *close = new QToolButton(m_messageBar);
    close->setText(tr("Dismiss"));
    close->setAutoRaise(true);
    connect(close, &QToolButton::clicked, this, &MainWindow::hideBarMessage);
    barLayout->addWidget(close);
    m_messageBar->hide();
    layout->addWidget(m_messageBar);
    layout->addWidget(m_view, 1);
    setCentralWidget(central);

    createActions();
    createMenus();
    createToolBars();
    addShortcutsToToolTips();
    createDocks();
    createStatusBar();
    // A click on a check box, a radio button, a button or a list box in a dock leaves the
    // keyboard where it was, as the Compare box does: ticking Kinetic energy and pressing Space
    // to play ticked the box again instead (a teacher tester's finding). Tabbed to, each still
    // takes the keys.
    for (QDockWidget *dock : findChildren<QDockWidget *>()) {
        for (QWidget *widget : dock->findChildren<QWidget *>()) {
            const bool clicked = qobject_cast<QAbstractButton *>(widget) || qobject_cast<QComboBox *>(widget);
            if (clicked && (widget->focusPolicy() & Qt::ClickFocus))
                widget->setFocusPolicy(Qt::TabFocus);
        }
    }

    connect(m_document, &SceneDocument::stepped, this, &MainWindow::updateFrameDisplay);
    connect(m_document, &SceneDocument::stepped, this, &MainWindow::updateEditActions);
    connect(m_document, &SceneDocument::sceneChanged, this, &MainWindow::onSceneChanged);
    connect(m_document, &SceneDocument::simulationFailed, this, &MainWindow::onSimulationFailed);
    connect(m_document, &SceneDocument::marblesHeld, this, &MainWindow::showStatus);
    // One refusal on show in the window, the latest, as within a dock.
    connect(m_parametersDock, &ParametersDock::refused, m_inspectorDock, &InspectorDock::clearRefusal);
    connect(m_inspectorDock, &InspectorDock::refused, m_parametersDock, &ParametersDock::clearRefusal);
    connect(m_document, &SceneDocument::fileNameChanged, this, &MainWindow::updateTitle);
    connect(m_document, &SceneDocument::modificationChanged, this, &MainWindow::updateTitle);
    connect(m_run, &RunController::runningChanged, this, &MainWindow::onRunningChanged);
    connect(m_view, &StageView::selectionChanged, this, &MainWindow::onSelectionChanged);
    connect(m_view, &StageView::message, this, &MainWindow::showStatus);
    connect(m_view, &StageView::frameMessage, this, &MainWindow::showFrameStatus);
    connect(m_document, &SceneDocument::stepped, this, &MainWindow::expireFrameStatus);
    // A new timeline (a marble added or removed, its undo) changes what the message said of the
    // frame, which stays the same ("Frame 59 is not kept" stayed after the undo of an add gave
    // frame 59 back): the stepped() that follows takes it away.
    connect(m_document, &SceneDocument::timelineReset, this,
            [this] { m_frameStatusAt = std::numeric_limits<std::int64_t>::min(); });
    connect(m_compare, &CompareRun::modelChanged, this, &MainWindow::updateCompareControls);
    connect(m_compare, &CompareRun::restarted, this, &MainWindow::updateCompareReadout);
    // Its dashed lines jump to the scene's values there: marked, not to be read as a collision.
    connect(m_compare, &CompareRun::restarted, this, [this] {
        if (m_compare->isTracking())
            m_plotDock->markCompareRestart(m_compare->startFrame());
    });
    connect(m_document, &SceneDocument::stepped, this, &MainWindow::updateCompareReadout);
    // An edit undone where it was made, the comparison back as it was: no restart there, but any
    // made before it (restart marks a frame apart are drawn as one, at the later).
    connect(m_compare, &CompareRun::restartTakenBack, this, [this](std::int64_t frame) {
        m_plotDock->unmarkCompareRestart(frame);
        for (const std::int64_t start : m_compare->restartFrames()) {
            if (start + 1 >= frame)
                m_plotDock->markCompareRestart(start);
        }
        updateCompareReadout();
    });

    m_autoSaver = new AutoSaver(m_document, QString(), this);
    m_autoSaver->start();
    connect(m_autoSaver, &AutoSaver::failed, this, [this] {
        // Its folder named, and both causes: it had asked "is the disk full?" of a folder that
        // was read-only (a helper's finding).
        showStatus(tr("The autosave could not be written in %1 (the disk full, or the folder read-only): save your "
                      "changes with Ctrl+S.")
                       .arg(QDir::toNativeSeparators(QFileInfo(m_autoSaver->scenePath()).absolutePath())));
    });
    // A second window cannot keep an autosave (the first one holds it): its first unsaved change
    // says so, rather than a crash losing it unannounced. (A lock that could not be written is
    // said by failed(), at each save that tries it again.)
    if (m_autoSaver->heldElsewhere()) {
        connect(m_document, &SceneDocument::modificationChanged, this, [this](bool modified) {
            if (modified && !m_warnedNoAutosave) {
                m_warnedNoAutosave = true;
                showStatus(tr("Changes in this window are not autosaved: another Marbles window keeps the autosave. "
                              "Save with Ctrl+S."));
            }
        });
    }

    World scene;
    makePreset(presets().front().id, scene);
    setPresetTitle(QString::fromStdString(presets().front().title));
    m_document->resetScene(scene);

    readSettings();
    m_settingsTimer = new QTimer(this);
    m_settingsTimer->setSingleShot(true);
    m_settingsTimer->setInterval(kSettingsWriteDelayMs);
    connect(m_settingsTimer, &QTimer::timeout, this, &MainWindow::writeSettings);
    for (QAction *toggle : {m_vectorsAction, m_trailsAction})
        connect(toggle, &QAction::toggled, this, &MainWindow::scheduleSettingsWrite);
    connect(m_speedBox, &QComboBox::currentIndexChanged, this, &MainWindow::scheduleSettingsWrite);
    connect(m_plotDock, &PlotDock::choicesChanged, this, &MainWindow::scheduleSettingsWrite);
    for (QDockWidget *dock : findChildren<QDockWidget *>(QString(), Qt::FindDirectChildrenOnly)) {
        connect(dock, &QDockWidget::dockLocationChanged, this, &MainWindow::scheduleSettingsWrite);
        connect(dock, &QDockWidget::topLevelChanged, this, &MainWindow::scheduleSettingsWrite);
        connect(dock, &QDockWidget::visibilityChanged, this, &MainWindow::scheduleSettingsWrite);
    }
    for (QToolBar *bar : findChildren<QToolBar *>(QString(), Qt::FindDirectChildrenOnly)) {
        connect(bar, &QToolBar::topLevelChanged, this, &MainWindow::scheduleSettingsWrite);
        connect(bar, &QToolBar::visibilityChanged, this, &MainWindow::scheduleSettingsWrite);
    }
    updateTitle();
    updateFrameDisplay();
    updateEditActions();
    updateStatistics();
    updateCompareControls();
    m_view->setFocus();
}

MainWindow::~MainWindow()
{
    // QObject destroys children only after ~QWidget has begun, when this is no longer a
    // MainWindow; a signal the document or the run loop sends while dying (QUndoStack emits
    // cleanChanged from its destructor) must not reach a slot here.
    const QList<QObject *> senders{m_document, m_run, m_view, m_autoSaver, m_compare};
    for (QObject *sender : senders) {
        if (sender)
            sender->disconnect(this);
    }
    // Nor may the docks and toolbars, hidden as the window closes, ask for the settings to be
    // written (UBSan: a slot of a MainWindow called on what was by then a QWidget).
    for (QObject *child : findChildren<QObject *>())
        child->disconnect(this);
    if (m_settingsTimer)
        m_settingsTimer->stop();
    if (m_inspectorDock)
        m_inspectorDock->setComparison({}, {}); // the comparison goes before the dock
}

namespace {

// Each key once, in order: a key listed twice is an ambiguous shortcut, which Qt ignores.
QList<QKeySequence> eachOnce(const QList<QKeySequence> &keys)
{
    QList<QKeySequence> once;
    for (const QKeySequence &key : keys) {
        if (!key.isEmpty() && !once.contains(key))
            once << key;
    }
    return once;
}

} // namespace

QList<QKeySequence> MainWindow::redoShortcuts(const QList<QKeySequence> &platformRedo)
{
    // (On X11 the platform's Redo is Ctrl+Shift+Z itself: listed twice, the keys did nothing.)
    // Ctrl+Y on every platform: a helper used to Windows pressed it on Linux, and nothing was redone.
    return eachOnce(QList<QKeySequence>{QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_Z), QKeySequence(Qt::CTRL | Qt::Key_Y)}
                    + platformRedo);
}

QList<QKeySequence> MainWindow::zoomInShortcuts(const QList<QKeySequence> &platformZoomIn)
{
    return eachOnce(platformZoomIn + QList<QKeySequence>{QKeySequence(Qt::CTRL | Qt::Key_Equal)});
}

void MainWindow::setPrompts(std::unique_ptr<Prompts> prompts)
{
    if (prompts)
        m_prompts = std::move(prompts);
}

void MainWindow::createActions()
{
    m_newAction = new QAction(themeIcon(QStringLiteral("document-new"), QStyle::SP_FileIcon), tr("&New"), this);
    m_newAction->setObjectName(QStringLiteral("actionNew"));
    m_newAction->setShortcut(QKeySequence::New);
    m_newAction->setStatusTip(tr("Start a new, empty scene (the chapter's scenes are under File > Presets)"));
    connect(m_newAction, &QAction::triggered, this, &MainWindow::newScene);

    m_openAction = new QAction(themeIcon(QStringLiteral("document-open"), QStyle::SP_DialogOpenButton), tr("&Open…"), this);
    m_openAction->setObjectName(QStringLiteral("actionOpen"));
    m_openAction->setShortcut(QKeySequence::Open);
    connect(m_openAction, &QAction::triggered, this, &MainWindow::open);

    m_saveAction = new QAction(themeIcon(QStringLiteral("document-save"), QStyle::SP_DialogSaveButton), tr("&Save"), this);
    m_saveAction->setObjectName(QStringLiteral("actionSave"));
    m_saveAction->setShortcut(QKeySequence::Save);
    connect(m_saveAction, &QAction::triggered, this, &MainWindow::save);

    m_saveAsAction = new QAction(QIcon::fromTheme(QStringLiteral("document-save-as")), tr("Save &As…"), this);
    m_saveAsAction->setObjectName(QStringLiteral("actionSaveAs"));
    // Ctrl+Shift+S everywhere: the platform's Save As is empty without a desktop's key theme.
    m_saveAsAction->setShortcuts(
        eachOnce(QKeySequence::keyBindings(QKeySequence::SaveAs) + QList<QKeySequence>{QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_S)}));
    connect(m_saveAsAction, &QAction::triggered, this, &MainWindow::saveAs);

    // The Plot dock's exports, from the menu too: its buttons are far from the keyboard.
    m_exportCsvAction = new QAction(tr("Export Plot &Data (CSV)…"), this);
    m_exportCsvAction->setObjectName(QStringLiteral("actionExportPlotCsv"));
    m_exportCsvAction->setStatusTip(tr("Save the plotted speeds, energy and momentum, frame by frame, as CSV"));
    connect(m_exportCsvAction, &QAction::triggered, this, [this] { m_plotDock->exportCsvInteractive(); });
    m_exportPngAction = new QAction(tr("Export Plot &Image (PNG)…"), this);
    m_exportPngAction->setObjectName(QStringLiteral("actionExportPlotPng"));
    m_exportPngAction->setStatusTip(tr("Save the plot as a picture, with a caption naming the scene and models"));
    connect(m_exportPngAction, &QAction::triggered, this, [this] { m_plotDock->exportPngInteractive(); });

    m_quitAction = new QAction(QIcon::fromTheme(QStringLiteral("application-exit")), tr("&Quit"), this);
    m_quitAction->setObjectName(QStringLiteral("actionQuit"));
    m_quitAction->setShortcut(QKeySequence::Quit);
    connect(m_quitAction, &QAction::triggered, this, &QWidget::close);

    m_undoAction = m_document->undoStack()->createUndoAction(this, tr("&Undo"));
    m_undoAction->setObjectName(QStringLiteral("actionUndo"));
    m_undoAction->setIcon(themeIcon(QStringLiteral("edit-undo"), QStyle::SP_ArrowBack));
    m_undoAction->setShortcut(QKeySequence::Undo);
    m_redoAction = m_document->undoStack()->createRedoAction(this, tr("&Redo"));
    m_redoAction->setObjectName(QStringLiteral("actionRedo"));
    m_redoAction->setIcon(themeIcon(QStringLiteral("edit-redo"), QStyle::SP_ArrowForward));
    m_redoAction->setShortcuts(redoShortcuts(QKeySequence::keyBindings(QKeySequence::Redo)));

    m_deleteAction = new QAction(themeIcon(QStringLiteral("edit-delete"), QStyle::SP_TrashIcon), tr("&Delete"), this);
    m_deleteAction->setObjectName(QStringLiteral("actionDelete"));
    m_deleteAction->setShortcut(QKeySequence::Delete);
    m_deleteAction->setStatusTip(tr("Delete the selected marble or pin"));
    connect(m_deleteAction, &QAction::triggered, m_view, &StageView::deleteSelection);

    m_toolGroup = new QActionGroup(this);
    m_toolGroup->setExclusive(true);
    m_selectToolAction = new QAction(tr("Select && Push"), m_toolGroup);
    m_selectToolAction->setObjectName(QStringLiteral("actionSelectTool"));
    m_selectToolAction->setShortcut(QKeySequence(Qt::Key_S));
    m_selectToolAction->setStatusTip(
        tr("Click a marble to push it (the further from its centre, the harder); drag marbles and pins to move them"));
    m_marbleToolAction = new QAction(tr("Add &Marble"), m_toolGroup);
    m_marbleToolAction->setObjectName(QStringLiteral("actionAddMarbleTool"));
    m_marbleToolAction->setShortcut(QKeySequence(Qt::Key_M));
    m_marbleToolAction->setStatusTip(tr("Click on the stage to add a marble"));
    m_pinToolAction = new QAction(tr("Add &Pin"), m_toolGroup);
    m_pinToolAction->setObjectName(QStringLiteral("actionAddPinTool"));
    m_pinToolAction->setShortcut(QKeySequence(Qt::Key_P));
    m_pinToolAction->setStatusTip(tr("Click on the stage to add a pin"));
    for (QAction *action : m_toolGroup->actions())
        action->setCheckable(true);
    m_selectToolAction->setChecked(true);
    connect(m_toolGroup, &QActionGroup::triggered, this, &MainWindow::onToolChosen);

    m_addMarbleHereAction = new QAction(tr("Add Marble Here"), this);
    m_addMarbleHereAction->setObjectName(QStringLiteral("actionAddMarbleHere"));
    connect(m_addMarbleHereAction, &QAction::triggered, this, &MainWindow::addMarbleHere);
    m_addPinHereAction = new QAction(tr("Add Pin Here"), this);
    m_addPinHereAction->setObjectName(QStringLiteral("actionAddPinHere"));
    connect(m_addPinHereAction, &QAction::triggered, this, &MainWindow::addPinHere);

    m_playAction = new QAction(themeIcon(QStringLiteral("media-playback-start"), QStyle::SP_MediaPlay), tr("&Play"), this);
    m_playAction->setObjectName(QStringLiteral("actionPlay"));
    m_playAction->setShortcut(QKeySequence(Qt::Key_Space));
    m_playAction->setStatusTip(tr("Run or pause the simulation"));
    connect(m_playAction, &QAction::triggered, this, &MainWindow::togglePlay);

    m_stepAction = new QAction(themeIcon(QStringLiteral("media-seek-forward"), QStyle::SP_MediaSeekForward), tr("S&tep"), this);
    m_stepAction->setObjectName(QStringLiteral("actionStep"));
    m_stepAction->setShortcut(QKeySequence(Qt::Key_Right));
    m_stepAction->setStatusTip(tr("Simulate one frame"));
    connect(m_stepAction, &QAction::triggered, this, &MainWindow::stepForward);

    m_stepBackAction = new QAction(themeIcon(QStringLiteral("media-seek-backward"), QStyle::SP_MediaSeekBackward), tr("Step &Back"), this);
    m_stepBackAction->setObjectName(QStringLiteral("actionStepBack"));
    m_stepBackAction->setShortcut(QKeySequence(Qt::Key_Left));
    m_stepBackAction->setStatusTip(tr("Go back one frame, exactly as it was"));
    connect(m_stepBackAction, &QAction::triggered, this, &MainWindow::stepBackward);

    m_rewindAction = new QAction(themeIcon(QStringLiteral("media-skip-backward"), QStyle::SP_MediaSkipBackward), tr("Back to &Start"), this);
    m_rewindAction->setObjectName(QStringLiteral("actionRewind"));
    m_rewindAction->setShortcut(QKeySequence(Qt::Key_Home));
    m_rewindAction->setStatusTip(tr("Go back to frame 0"));
    connect(m_rewindAction, &QAction::triggered, this, &MainWindow::rewindToStart);

    // The run speed from the keyboard and the menu, as a video site's < and >: slow motion for a
    // collision was only in the toolbar's box, which the keyboard does not reach.
    m_slowerAction = new QAction(tr("Run Slo&wer"), this);
    m_slowerAction->setObjectName(QStringLiteral("actionSlower"));
    // With Shift as well, as the key arrives where < and > are shifted keys (most layouts).
    m_slowerAction->setShortcuts({QKeySequence(Qt::Key_Less), QKeySequence(Qt::SHIFT | Qt::Key_Less)});
    m_slowerAction->setStatusTip(tr("Run at the next slower speed, down to 0.1×: slow motion"));
    connect(m_slowerAction, &QAction::triggered, this, [this] { stepSpeed(-1); });
    m_fasterAction = new QAction(tr("Run &Faster"), this);
    m_fasterAction->setObjectName(QStringLiteral("actionFaster"));
    m_fasterAction->setShortcuts({QKeySequence(Qt::Key_Greater), QKeySequence(Qt::SHIFT | Qt::Key_Greater)});
    m_fasterAction->setStatusTip(tr("Run at the next faster speed, up to 4×"));
    connect(m_fasterAction, &QAction::triggered, this, [this] { stepSpeed(1); });

    // The stage from the keyboard: choose a marble, push it (a click needs the mouse).
    m_nextMarbleAction = new QAction(tr("Select &Next Marble"), this);
    m_nextMarbleAction->setObjectName(QStringLiteral("actionNextMarble"));
    m_nextMarbleAction->setShortcut(QKeySequence(Qt::Key_BracketRight));
    connect(m_nextMarbleAction, &QAction::triggered, this, [this] { m_view->selectNextMarble(1); });
    m_previousMarbleAction = new QAction(tr("Select Pre&vious Marble"), this);
    m_previousMarbleAction->setObjectName(QStringLiteral("actionPreviousMarble"));
    m_previousMarbleAction->setShortcut(QKeySequence(Qt::Key_BracketLeft));
    connect(m_previousMarbleAction, &QAction::triggered, this, [this] { m_view->selectNextMarble(-1); });
    // Nothing selected: the plot shows the first twelve marbles again (in a crowd, clicking the
    // stage's margin was the only way).
    m_clearSelectionAction = new QAction(tr("Clear Se&lection"), this);
    m_clearSelectionAction->setObjectName(QStringLiteral("actionClearSelection"));
    m_clearSelectionAction->setShortcut(QKeySequence(Qt::Key_Escape));
    // Esc first takes back a click's push still to act (a click meant to select the marble, or on
    // the wrong one: a click is not an edit, Ctrl+Z undid the edit before it and the push stayed),
    // then, pressed again, clears the selection.
    connect(m_clearSelectionAction, &QAction::triggered, this, [this] {
        if (const int taken = m_document->takeBackPushes(); taken > 0) {
            showFrameStatus(taken == 1 ? tr("Push taken back: it will not act.")
                                       : tr("Pushes on %1 marbles taken back: they will not act.").arg(taken));
            return;
        }
        m_view->clearSelection();
    });
    const struct {
        const char *name;
        const char *text;
        Qt::Key key;
        Vec2 direction;
    } pushes[] = {
        {"actionPushLeft", QT_TR_NOOP("Push Selected Marble &Left"), Qt::Key_Left, {-1, 0}},
        {"actionPushRight", QT_TR_NOOP("Push Selected Marble &Right"), Qt::Key_Right, {1, 0}},
        {"actionPushUp", QT_TR_NOOP("Push Selected Marble &Up"), Qt::Key_Up, {0, -1}},
        {"actionPushDown", QT_TR_NOOP("Push Selected Marble &Down"), Qt::Key_Down, {0, 1}},
    };
    for (const auto &push : pushes) {
        auto *action = new QAction(tr(push.text), this);
        action->setObjectName(QLatin1String(push.name));
        action->setShortcut(QKeySequence(Qt::SHIFT | push.key));
        action->setStatusTip(tr("As a click on the selected marble's far edge would"));
        const Vec2 direction = push.direction;
        connect(action, &QAction::triggered, this, [this, direction] {
            if (!m_view->pushSelected(direction))
                showStatus(tr("Select a marble first: click it, or ] and [ go through the marbles."));
        });
        m_pushActions.append(action);
    }

    m_fitAction = new QAction(QIcon::fromTheme(QStringLiteral("zoom-fit-best")), tr("&Fit to Stage"), this);
    m_fitAction->setObjectName(QStringLiteral("actionFit"));
    // Short toolbar labels (the menus keep the full names), so that every tool stays on the
    // toolbar of a 1400 px wide window instead of moving into its overflow menu.
    m_fitAction->setIconText(tr("Fit"));
    m_fitAction->setToolTip(tr("Fit to Stage: zoom so that the whole stage shows"));
    m_fitAction->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_0));
    connect(m_fitAction, &QAction::triggered, m_view, &StageView::fitToStage);
    m_zoomInAction = new QAction(QIcon::fromTheme(QStringLiteral("zoom-in")), tr("Zoom &In"), this);
    m_zoomInAction->setObjectName(QStringLiteral("actionZoomIn"));
    m_zoomInAction->setShortcuts(zoomInShortcuts(QKeySequence::keyBindings(QKeySequence::ZoomIn)));
    connect(m_zoomInAction, &QAction::triggered, this, [this] { m_view->zoomBy(1.25); });
    m_zoomOutAction = new QAction(QIcon::fromTheme(QStringLiteral("zoom-out")), tr("Zoom &Out"), this);
    m_zoomOutAction->setObjectName(QStringLiteral("actionZoomOut"));
    m_zoomOutAction->setShortcut(QKeySequence::ZoomOut);
    connect(m_zoomOutAction, &QAction::triggered, this, [this] { m_view->zoomBy(1.0 / 1.25); });

    m_vectorsAction = new QAction(tr("Collision &Vectors"), this);
    m_vectorsAction->setObjectName(QStringLiteral("actionVectors"));
    m_vectorsAction->setIconText(tr("Vectors"));
    m_vectorsAction->setToolTip(tr("Collision vectors at each marble's last collision (Figure 11.12)"));
    m_vectorsAction->setCheckable(true);
    m_vectorsAction->setChecked(m_view->vectorsVisible());
    m_vectorsAction->setShortcut(QKeySequence(Qt::Key_V));
    m_vectorsAction->setStatusTip(tr("Figure 11.12: velocity (blue), collision vector (red), reflected velocity (green) "
                                     "at each marble's last collision"));
    connect(m_vectorsAction, &QAction::toggled, m_view, &StageView::setVectorsVisible);
    m_trailsAction = new QAction(tr("&Trails"), this);
    m_trailsAction->setObjectName(QStringLiteral("actionTrails"));
    m_trailsAction->setCheckable(true);
    m_trailsAction->setChecked(m_view->trailsVisible());
    m_trailsAction->setShortcut(QKeySequence(Qt::Key_T));
    m_trailsAction->setStatusTip(tr("Fading trails behind the marbles; the selected marble's is kept long and drawn dark"));
    connect(m_trailsAction, &QAction::toggled, m_view, &StageView::setTrailsVisible);

    // Compare With: one checkable action per model, shared by the Simulation menu and the toolbar box.
    m_compareGroup = new QActionGroup(this);
    m_compareGroup->setExclusive(true);
    const auto addCompareAction = [this](const QString &text, const QString &name, int data, const QString &tip) {
        auto *action = new QAction(text, m_compareGroup);
        action->setObjectName(name);
        action->setCheckable(true);
        action->setData(data);
        action->setStatusTip(tip);
    };
    addCompareAction(tr("&None"), QStringLiteral("actionCompareNone"), -1, tr("Run the scene's own model only"));
    addCompareAction(tr("&Book"), QStringLiteral("actionCompareBook"), static_cast<int>(ModelKind::Book),
                     tr("Run the chapter's model beside this one: its marbles appear as dashed outlines"));
    addCompareAction(tr("&Exact"), QStringLiteral("actionCompareExact"), static_cast<int>(ModelKind::Exact),
                     tr("Run the exact reference physics beside this model: its marbles appear as dashed outlines"));
    addCompareAction(tr("&Impulse"), QStringLiteral("actionCompareImpulse"), static_cast<int>(ModelKind::Impulse),
                     tr("Run the games' impulse model beside this one: its marbles appear as dashed outlines"));
    m_compareGroup->actions().front()->setChecked(true);
    connect(m_compareGroup, &QActionGroup::triggered, this, &MainWindow::onCompareChosen);

    addActions({m_playAction, m_stepAction, m_stepBackAction, m_rewindAction});
    m_view->setContextActions({m_selectToolAction, m_marbleToolAction, m_pinToolAction, nullptr, m_addMarbleHereAction,
                               m_addPinHereAction, nullptr, m_deleteAction});
}

void MainWindow::createMenus()
{
    QMenu *file = menuBar()->addMenu(tr("&File"));
    file->addAction(m_newAction);
    file->addAction(m_openAction);
    m_recentMenu = file->addMenu(tr("Open &Recent"));
    m_recentMenu->setObjectName(QStringLiteral("recentMenu"));
    m_presetMenu = file->addMenu(tr("&Presets"));
    m_presetMenu->setObjectName(QStringLiteral("presetMenu"));
    for (const PresetInfo &preset : presets()) {
        QAction *action = m_presetMenu->addAction(QString::fromStdString(preset.title));
        action->setObjectName(QStringLiteral("preset-") + QString::fromStdString(preset.id));
        action->setData(QString::fromStdString(preset.id));
        action->setStatusTip(QString::fromStdString(preset.description));
        action->setToolTip(QString::fromStdString(preset.description));
        connect(action, &QAction::triggered, this, [this, action] { openPreset(action->data().toString()); });
    }
    file->addSeparator();
    file->addAction(m_saveAction);
    file->addAction(m_saveAsAction);
    file->addSeparator();
    file->addAction(m_exportCsvAction);
    file->addAction(m_exportPngAction);
    file->addSeparator();
    file->addAction(m_quitAction);
    rebuildRecentMenu();

    QMenu *edit = menuBar()->addMenu(tr("&Edit"));
    edit->addAction(m_undoAction);
    edit->addAction(m_redoAction);
    edit->addSeparator();
    edit->addAction(m_selectToolAction);
    edit->addAction(m_marbleToolAction);
    edit->addAction(m_pinToolAction);
    edit->addSeparator();
    edit->addAction(m_nextMarbleAction);
    edit->addAction(m_previousMarbleAction);
    edit->addAction(m_clearSelectionAction);
    edit->addSeparator();
    edit->addAction(m_deleteAction);

    QMenu *simulation = menuBar()->addMenu(tr("&Simulation"));
    simulation->addAction(m_playAction);
    simulation->addAction(m_stepAction);
    simulation->addAction(m_stepBackAction);
    simulation->addAction(m_rewindAction);
    simulation->addSeparator();
    simulation->addAction(m_slowerAction);
    simulation->addAction(m_fasterAction);
    simulation->addSeparator();
    simulation->addActions(m_pushActions);
    simulation->addSeparator();
    m_compareMenu = simulation->addMenu(tr("&Compare With"));
    m_compareMenu->setObjectName(QStringLiteral("compareMenu"));
    m_compareMenu->addActions(m_compareGroup->actions());

    m_viewMenu = menuBar()->addMenu(tr("&View"));
    m_viewMenu->addAction(m_vectorsAction);
    m_viewMenu->addAction(m_trailsAction);
    m_viewMenu->addSeparator();
    m_viewMenu->addAction(m_fitAction);
    m_viewMenu->addAction(m_zoomInAction);
    m_viewMenu->addAction(m_zoomOutAction);
    m_viewMenu->addSeparator();

    QMenu *help = menuBar()->addMenu(tr("&Help"));
    QAction *keys = help->addAction(tr("&Keyboard and Mouse"), this, &MainWindow::showKeysAndMouse);
    keys->setObjectName(QStringLiteral("actionKeysAndMouse"));
    keys->setShortcut(QKeySequence::HelpContents);
    help->addSeparator();
    QAction *about = help->addAction(tr("&About Marbles"), this, [this] {
        QMessageBox::about(
            this, tr("About Marbles"),
            tr("<p><b>Marbles %1</b></p>"
               "<p>A physics lesson you can play with: the marbles of chapter 11 of a game-programming "
               "book, step by step (the <i>book</i> model, its shortcuts included), beside the exact "
               "physics (collisions at their exact moment, momentum kept in every hit between marbles) and a game engine's "
               "<i>impulse</i> model, so that a class can see where the shortcuts go wrong.</p>"
               "<p>Running with Qt %2.</p>")
                .arg(QCoreApplication::applicationVersion(), QString::fromLatin1(qVersion())));
    });
    about->setObjectName(QStringLiteral("actionAbout"));
    QAction *aboutQt = help->addAction(tr("About &Qt"), qApp, &QApplication::aboutQt);
    aboutQt->setObjectName(QStringLiteral("actionAboutQt"));
}

namespace {

// A menu text without its mnemonic marks ("&&" is a literal "&": "Select && Push").
QString withoutMnemonics(QString text)
{
    text.replace(QStringLiteral("&&"), QStringLiteral("\u0001")).remove(QLatin1Char('&'));
    return text.replace(QChar(1), QLatin1Char('&'));
}

// "Play (Space)": an action's text without its mnemonic marks or ellipsis, and its shortcut.
QString withShortcut(const QAction *action)
{
    QString text = withoutMnemonics(action->text());
    text.remove(QStringLiteral("\u2026")).remove(QStringLiteral("..."));
    return action->shortcut().isEmpty()
        ? text
        : QStringLiteral("%1 (%2)").arg(text, action->shortcut().toString(QKeySequence::NativeText));
}

} // namespace

void MainWindow::showKeysAndMouse()
{
    // Built from the actions themselves, so the list is the shortcuts the window really has.
    if (!m_keysDialog) {
        m_keysDialog = new QDialog(this);
        m_keysDialog->setObjectName(QStringLiteral("keysDialog"));
        m_keysDialog->setWindowTitle(tr("Keyboard and Mouse"));
        auto *layout = new QVBoxLayout(m_keysDialog);
        auto *text = new QLabel(m_keysDialog);
        text->setObjectName(QStringLiteral("keysText"));
        text->setTextFormat(Qt::RichText);
        // In a scroll area: on a projector at a scale of 2 the list was taller than the screen,
        // its last rows and Close below the edge.
        auto *scroll = new QScrollArea(m_keysDialog);
        scroll->setWidget(text);
        scroll->setWidgetResizable(true);
        scroll->setFrameShape(QFrame::NoFrame);
        layout->addWidget(scroll);
        auto *buttons = new QDialogButtonBox(QDialogButtonBox::Close, m_keysDialog);
        connect(buttons, &QDialogButtonBox::rejected, m_keysDialog, &QDialog::close);
        layout->addWidget(buttons);
    }
    QString rows;
    const auto row = [&rows](const QString &what, const QString &how) {
        // A column of its own between the two, so that a wrapped line starts where its first did.
        rows += QStringLiteral("<tr><td>%1</td><td width=12></td><td>%2</td></tr>").arg(what.toHtmlEscaped(), how.toHtmlEscaped());
    };
    for (QMenu *menu : menuBar()->findChildren<QMenu *>(Qt::FindDirectChildrenOnly)) {
        for (const QAction *action : menu->actions()) {
            if (!action->shortcut().isEmpty()) {
                // Undo and Redo by their names, not the edit they would undo now.
                const QString text = action == m_undoAction   ? tr("Undo")
                                     : action == m_redoAction ? tr("Redo")
                                     : action == m_playAction ? tr("Play / Pause")
                                                              : withoutMnemonics(action->text());
                // Every key of it (Redo's Ctrl+Y was left out, behind Ctrl+Shift+Z).
                QStringList keys;
                for (const QKeySequence &key : action->shortcuts())
                    keys << key.toString(QKeySequence::NativeText);
                row(text, keys.join(QStringLiteral(", ")));
            }
        }
    }
    rows += QStringLiteral("<tr><td colspan=3>&nbsp;</td></tr>");
    row(tr("Click a marble"), tr("push it: further from its centre pushes harder, away from the click"));
    row(tr("The push"), tr("acts on the next frame; an arrow shows it until then (clicks add up), as it does a scene's scripted push; Esc takes it back"));
    row(tr("The marble clicked"), tr("is selected: inspected, plotted, and with Trails on its trail kept long"));
    row(tr("Drag a marble or a pin"), tr("move it (paused or running)"));
    row(tr("Right-click"), tr("add or delete here"));
    row(tr("Menu key, Shift+F10"), tr("the same menu, at the marble or pin selected or in the middle of the stage"));
    row(tr("Wheel"), tr("zoom"));
    rows += QStringLiteral("<tr><td colspan=3>&nbsp;</td></tr>");
    row(tr("Tab, Shift+Tab"), tr("from control to control; Space presses a button or ticks a box tabbed to (one clicked leaves the keys on the stage)"));
    row(tr("Alt + a field's underlined letter"), tr("to that field (Enter takes a number typed; Space takes it and plays; Esc puts the number back and returns to the stage); a check box's letter ticks or clears it"));
    row(tr("Esc in a dock or a toolbar"), tr("back to the stage, which a frame in the highlight colour marks while it has the keys"));
    row(tr("View > a dock's name"), tr("shows that dock in front of its tabs (the Undo History behind the Inspector), or hides it when in front"));
    auto *label = m_keysDialog->findChild<QLabel *>(QStringLiteral("keysText"));
    label->setText(QStringLiteral("<table>%1</table>").arg(rows));
    // As large as the list asks, within the screen; narrower than its lines, it wraps them (at
    // 1024 x 768 the long ones ran past the dialog's edge, read by scrolling sideways: a
    // helper's finding).
    label->setWordWrap(false);
    const QSize wanted = label->sizeHint() + QSize(48, 96);
    label->setWordWrap(true);
    const QSize room = screen() ? screen()->availableGeometry().size() * 9 / 10 : wanted;
    m_keysDialog->resize(wanted.boundedTo(room));
    m_keysDialog->show();
    m_keysDialog->raise();
    m_keysDialog->activateWindow();
}


void MainWindow::addShortcutsToToolTips()
{
    // A toolbar button's tip names its key, as the menus do: the buttons are what a class sees.
    for (QToolBar *bar : findChildren<QToolBar *>()) {
        for (QAction *action : bar->actions()) {
            if (!action->shortcut().isEmpty())
                action->setToolTip(withShortcut(action));
        }
    }
    // Undo's and Redo's texts follow the stack ("Undo Set friction to 0.2"): their tips too.
    // The actions are the receivers, not the window: the stack says its texts changed once more
    // as it is cleared, while the window is being destroyed (UBSan: a member access within an
    // object no longer a MainWindow).
    QUndoStack *stack = m_document->undoStack();
    for (QAction *action : {m_undoAction, m_redoAction}) {
        connect(stack, action == m_undoAction ? &QUndoStack::undoTextChanged : &QUndoStack::redoTextChanged, action,
                [action] { action->setToolTip(withShortcut(action)); });
    }
}

void MainWindow::createToolBars()
{
    QToolBar *fileBar = addToolBar(tr("File"));
    fileBar->setObjectName(QStringLiteral("fileToolBar"));
    fileBar->addAction(m_newAction);
    fileBar->addAction(m_openAction);
    fileBar->addAction(m_saveAction);
    fileBar->addSeparator();
    fileBar->addAction(m_undoAction);
    fileBar->addAction(m_redoAction);

    QToolBar *runBar = addToolBar(tr("Run"));
    runBar->setObjectName(QStringLiteral("runToolBar"));
    runBar->addAction(m_rewindAction);
    runBar->addAction(m_stepBackAction);
    runBar->addAction(m_playAction);
    runBar->addAction(m_stepAction);
    // Play/Pause is the button everyone looks for: it carries its name; the others show it on hover.
    if (auto *play = qobject_cast<QToolButton *>(runBar->widgetForAction(m_playAction))) {
        play->setToolButtonStyle(Qt::ToolButtonTextBesideIcon);
        play->setMinimumWidth(80);
    }
    m_speedBox = new QComboBox(runBar);
    m_speedBox->setObjectName(QStringLiteral("speedBox"));
    m_speedBox->setAccessibleName(tr("Run speed"));
    m_speedBox->setToolTip(tr("Run speed: simulated time per wall-clock time (%1 slower, %2 faster)")
                               .arg(m_slowerAction->shortcut().toString(QKeySequence::NativeText),
                                    m_fasterAction->shortcut().toString(QKeySequence::NativeText)));
    m_speedBox->setFocusPolicy(Qt::NoFocus);
    for (double speed : kSpeeds)
        m_speedBox->addItem(QStringLiteral("%1×").arg(shownNumber(speed)), speed);
    m_speedBox->setCurrentIndex(kRealTimeSpeedIndex);
    connect(m_speedBox, &QComboBox::currentIndexChanged, this, &MainWindow::onSpeedChosen);
    runBar->addWidget(m_speedBox);
    runBar->addSeparator();
    m_frameDisplay = new QLabel(runBar);
    m_frameDisplay->setObjectName(QStringLiteral("frameDisplay"));
    // Wide enough for "Frame 999999   t = 99999.99 s": the Compare box and the tools after it
    // stayed put as the frame number grew (they moved under the pointer).
    m_frameDisplay->setContentsMargins(8, 0, 8, 0);
    QFont font = m_frameDisplay->font();
    font.setPointSizeF(font.pointSizeF() * 1.15);
    font.setBold(true);
    m_frameDisplay->setFont(font);
    m_frameDisplay->setMinimumWidth(
        QFontMetrics(font).horizontalAdvance(tr("Frame %1   t = %2 s").arg(999999).arg(shownNumber(99999.99, 'f', 2))) + 16);
    runBar->addWidget(m_frameDisplay);
    // A bar of its own, so that on a narrow window (half of a 1366-px laptop screen) it takes
    // the next row rather than the run bar's overflow menu.
    QToolBar *compareBar = addToolBar(tr("Compare"));
    compareBar->setObjectName(QStringLiteral("compareToolBar"));
    m_compareBox = new QComboBox(compareBar);
    m_compareBox->setObjectName(QStringLiteral("compareBox"));
    // Named for a screen reader, which read out only its current text (a helper's finding).
    m_compareBox->setAccessibleName(tr("Compare with a second model"));
    m_compareBoxToolTip = tr("Run a second model beside this one on the same scene; its marbles are drawn "
                             "as dashed outlines and its speeds as dashed lines in the plot");
    m_compareBox->setToolTip(m_compareBoxToolTip);
    m_compareBox->setFocusPolicy(Qt::TabFocus);
    // Wide enough for its longest text, "Compare: impulse (paused)", set once: a box that grew
    // with its text moved the tools after it under the pointer.
    m_compareBox->addItem(tr("Compare: %1 (paused)").arg(QStringLiteral("impulse")));
    m_compareBox->setMinimumWidth(m_compareBox->sizeHint().width());
    m_compareBox->clear(); // filled by updateCompareControls()
    connect(m_compareBox, &QComboBox::activated, this, [this](int index) {
        const int data = m_compareBox->itemData(index).toInt();
        for (QAction *action : m_compareGroup->actions()) {
            if (action->data().toInt() == data && !action->isChecked())
                action->trigger();
        }
    });
    compareBar->addWidget(m_compareBox);

    QToolBar *toolBar = addToolBar(tr("Tools"));
    toolBar->setObjectName(QStringLiteral("toolsToolBar"));
    toolBar->setToolButtonStyle(Qt::ToolButtonTextOnly);
    toolBar->addAction(m_selectToolAction);
    toolBar->addAction(m_marbleToolAction);
    toolBar->addAction(m_pinToolAction);
    toolBar->addAction(m_deleteAction);
    toolBar->addSeparator();
    toolBar->addAction(m_vectorsAction);
    toolBar->addAction(m_trailsAction);
    toolBar->addAction(m_fitAction);
}

void MainWindow::createDocks()
{
    // The right-hand docks run the full height; the plot sits under the stage only.
    setCorner(Qt::BottomRightCorner, Qt::RightDockWidgetArea);
    m_parametersDock = new ParametersDock(this);
    addDockWidget(Qt::RightDockWidgetArea, m_parametersDock);
    connect(m_parametersDock, &ParametersDock::paramEdited, this, &MainWindow::onParamEdited);

    m_inspectorDock = new InspectorDock(m_document, this);
    m_inspectorDock->setComparison([this] { return m_compare->world(); },
                                   [this] { return QString::fromLatin1(modelName(m_compare->model())); });
    addDockWidget(Qt::RightDockWidgetArea, m_inspectorDock);
    connect(m_inspectorDock, &InspectorDock::message, this, &MainWindow::showStatus);

    m_historyDock = new QDockWidget(tr("Undo History"), this);
    m_historyDock->setObjectName(QStringLiteral("historyDock"));
    auto *undoView = new QUndoView(m_document->undoStack(), m_historyDock);
    undoView->setEmptyLabel(tr("<scene opened>"));
    undoView->setAccessibleName(tr("Undo history"));
    m_historyDock->setWidget(undoView);
    addDockWidget(Qt::RightDockWidgetArea, m_historyDock);
    tabifyDockWidget(m_inspectorDock, m_historyDock);
    m_inspectorDock->raise();

    m_plotDock = new PlotDock(this);
    addDockWidget(Qt::BottomDockWidgetArea, m_plotDock);
    // The plotted marbles drawn in their lines' colours: which line is which marble, at a glance.
    connect(m_plotDock, &PlotDock::plottedChanged, this, &MainWindow::tintPlottedMarbles);
    tintPlottedMarbles();
    connect(m_plotDock, &PlotDock::exported, this,
            [this](const QString &path) { showStatus(tr("Plot exported to %1").arg(QDir::toNativeSeparators(path))); });
    connect(m_document, &SceneDocument::frameAdvanced, this,
            [this] { m_plotDock->appendFrame(m_document->world(), m_compare->world()); });
    // The comparison restarted on this signal before (its connection is older): both worlds are at
    // the timeline's first frame, which the lines start from.
    // The lines run on through the frames Step Back can still go to: after a marble left mid-run
    // or came back, the kept frames followed it (they had started again at the edit, and Step
    // Back past it left one dot); a new timeline keeps none, and the lines start where it does.
    const auto replotKeptFrames = [this] {
        m_plotDock->replayKeptFrames(m_document->world(), m_compare->world(),
                                     m_document->history().firstUnbrokenFrame(m_document->world().frame));
        if (m_compare->isTracking()) {
            for (const std::int64_t frame : m_compare->restartFrames())
                m_plotDock->markCompareRestart(frame);
        }
    };
    connect(m_document, &SceneDocument::timelineReset, this, replotKeptFrames);
    // Colours follow the marbles through deletes and their undos (a new scene starts them over).
    connect(m_document, &SceneDocument::marbleRemovedAt, this,
            [this](int i) { m_plotDock->marbleRemovedAt(i, m_document->world().marbleCount() + 1); });
    connect(m_document, &SceneDocument::marbleInsertedAt, this,
            [this](int i) {
                const World &world = m_document->world();
                m_plotDock->marbleInsertedAt(i, world.marbleCount(), world.mass[static_cast<std::size_t>(i)]);
            });
    connect(m_document, &SceneDocument::sceneChanged, this, [this](SceneDocument::Change change) {
        if (change == SceneDocument::Change::Scene)
            m_plotDock->forgetColourOrder();
    });
    // An edit that keeps the marbles (friction changed mid-run, say) bends the lines where it was
    // made rather than wiping the run before it.
    connect(m_document, &SceneDocument::timelineEdited, this,
            [this] { m_plotDock->resample(m_document->world(), m_compare->world()); });
    // Back to a frame: the later samples go, and that frame's is taken again. A comparison that
    // cannot step back there (its kept frames start later, at an edit) starts again from the
    // scene's frame, so that the dashed lines meet the solid ones where the ghosts do (they
    // stayed apart there); and after a run longer than the plot holds, Home found no sample of
    // frame 0 left, and the plot was empty. Back past the plot's oldest samples (Step Back held
    // down through a run longer than the plot holds, or the undo of an edit made long before),
    // the lines are drawn again from the kept frames, as far back as the plot holds: the plot was
    // left with the few samples before the frame, or a single dot. It is drawn again once a
    // tenth of the plot is missing (holding Step Back down redraws once every tenth of the plot),
    // and once more when every kept frame fits, so that the lines reach back to where they start.
    connect(m_document, &SceneDocument::timelineRewound, this, [this, replotKeptFrames](std::int64_t frame) {
        m_plotDock->cutAfter(frame);
        const std::int64_t kept = frame - m_document->history().firstUnbrokenFrame(frame) + 1;
        const qsizetype capacity = m_plotDock->capacity();
        const qsizetype held = m_plotDock->sampleCount();
        if (held < std::min<std::int64_t>(kept, capacity) && (kept <= capacity || held + capacity / 10 < capacity))
            replotKeptFrames();
        else
            m_plotDock->resample(m_document->world(), m_compare->world());
    });
    // A marble selected after a run is plotted from as far back as Step Back can go.
    m_plotDock->setVelocityLookup(
        [this](std::int64_t frame) { return m_document->history().velocitiesAt(frame, m_document->world()); },
        [this](std::int64_t frame) { return m_compare->velocitiesAt(frame); });

    const std::pair<QDockWidget *, QString> docks[] = {
        {m_parametersDock, tr("&Parameters")},
        {m_inspectorDock, tr("I&nspector")},
        {m_historyDock, tr("&Undo History")},
        {m_plotDock, tr("P&lot")},
    };
    for (const auto &[dock, menuText] : docks) {
        // A dock whose tab gives way to another's is not hidden, only moved out of sight, and the
        // keys stayed in its field: a value typed in the Inspector, then the Undo History's tab
        // clicked, and Right and Delete worked the unseen field instead of the run and the
        // selection. They go back to the stage. Its contents are disabled until its tab is in
        // front again: Tab led into the unseen Undo History, where Up and Down undid and redid
        // edits with nothing on screen to show it (a helper's finding).
        connect(dock, &QDockWidget::visibilityChanged, this, [this, dock](bool visible) {
            if (!visible && dock->isAncestorOf(QApplication::focusWidget()))
                m_view->setFocus(Qt::OtherFocusReason);
            if (QWidget *contents = dock->widget())
                contents->setEnabled(visible);
        });
        // The View menu's item for a dock hidden shows it in front of its tabs, and for a dock
        // behind another's tab brings it to the front (the dock's own toggle hid it: the Undo
        // History could be reached by a click on its tab alone); for a dock in front it hides it.
        auto *action = new QAction(menuText, this);
        action->setObjectName(dock->objectName() + QStringLiteral("Action"));
        action->setCheckable(true);
        action->setChecked(!dock->isHidden());
        connect(dock->toggleViewAction(), &QAction::toggled, action, &QAction::setChecked);
        connect(action, &QAction::triggered, this, [this, dock, action] {
            const bool inFront = dock->widget() && dock->widget()->isEnabled();
            if (dock->isHidden() || !inFront) {
                dock->show();
                dock->raise();
            } else {
                dock->hide();
            }
            action->setChecked(!dock->isHidden());
        });
        m_viewMenu->addAction(action);
    }
}

void MainWindow::createStatusBar()
{
    setStatusBar(new ElidingStatusBar(this));
    const auto addLabel = [this](const QString &name, const QString &tip) {
        auto *label = new QLabel(this);
        label->setObjectName(name);
        label->setToolTip(tip);
        statusBar()->addPermanentWidget(label);
        return label;
    };
    m_frameLabel = addLabel(QStringLiteral("frameLabel"), tr("Frames simulated since frame 0"));
    m_timeLabel = addLabel(QStringLiteral("timeLabel"), tr("Simulated time: frame × frame interval / 1000, in seconds"));
    m_countLabel = addLabel(QStringLiteral("countLabel"), tr("Marbles and pins on the stage"));
    m_physicsLabel = addLabel(QStringLiteral("physicsLabel"), tr("Time the model takes to compute a frame (average of the last 30 or so; keeping the frame for stepping back is not counted)"));
    m_fpsLabel = addLabel(QStringLiteral("fpsLabel"), tr("Times per second the stage was redrawn (0 while nothing moves)"));
    m_slowLabel = addLabel(QStringLiteral("slowLabel"),
                           tr("This computer takes longer to compute a frame than the frame lasts, so the run goes\n"
                              "slower than the chosen speed and the stage keeps moving smoothly instead of jumping.\n"
                              "Fewer marbles, no comparison, or the book or impulse model run faster."));
    m_slowLabel->setVisible(false);
    // While comparing they give both models' totals, too long for a narrow window's bar: cut
    // with "…" there (their whole text in the tool tip), they leave the bar room for the rest.
    // Each one's "what" property, the first line of its tip above its whole text (setTotal()),
    // is given with its figures (updateStatistics()), in the plot's unit.
    const auto addTotal = [this](const QString &name) {
        auto *label = new ElidingLabel(this);
        label->setObjectName(name);
        statusBar()->addPermanentWidget(label);
        return label;
    };
    m_energyLabel = addTotal(QStringLiteral("energyLabel"));
    m_momentumLabel = addTotal(QStringLiteral("momentumLabel"));
    // The comparison readout comes first, where the eye lands after the stage; shown while comparing.
    m_compareLabel = new ElidingLabel(this);
    m_compareLabel->setObjectName(QStringLiteral("compareLabel"));
    m_compareLabel->setContentsMargins(0, 0, 12, 0);
    m_compareToolTip =
        tr("Largest distance between a marble and its dashed ghost since the comparison started.\n"
           "Both models start from the same state and run the same frames; a click pushes both.\n"
           "An edit starts the comparison again from the scene as it is then (Step Back past the edit\n"
           "returns to the comparison before it); Back to Start or a new scene starts it over.");
    m_compareLabel->setToolTip(m_compareToolTip);
    m_compareLabel->setVisible(false);
    // Its text can be long ("Compare: exact - not running: it needs a friction below 1 ..."):
    // a label asks for its whole text's width, and on a 1024 x 768 projector that pushed the
    // window past the screen's edge. It takes the room there is, its text cut with "…" (it
    // ended mid-word, "...: it n"); its tool tip has the whole text.
    statusBar()->insertPermanentWidget(0, m_compareLabel);
    // A message (a refusal's why, a preset's description) gets its room from these, which elide.
    static_cast<ElidingStatusBar *>(statusBar())->setYielding({m_compareLabel, m_energyLabel, m_momentumLabel});
    // The run toolbar shows the frame and the time in large type; the status bar repeats them
    // only while that toolbar is hidden, which leaves room for the comparison's readout.
    if (auto *runBar = findChild<QToolBar *>(QStringLiteral("runToolBar")))
        connect(runBar, &QToolBar::visibilityChanged, this, &MainWindow::updateFrameLabelsShown);
    updateFrameLabelsShown();
    m_statisticsClock.start();
    m_statisticsTimer = new QTimer(this);
    m_statisticsTimer->setInterval(250);
    connect(m_statisticsTimer, &QTimer::timeout, this, &MainWindow::updateStatistics);
    m_statisticsTimer->start();
}

void MainWindow::fitScreenHeight(int availableHeight)
{
    // The stage's and the plot's smallest sizes suit a laptop or a 1024 x 768 projector; on a
    // screen less tall (800 x 600) they would push the status bar and the plot's legend below
    // its edge: there both may shrink, to still readable sizes.
    // Below 600 px (a 1080p projector at a scale of 2 is 540 px tall) the stage's smallest height
    // goes down again: the window came out 546 px tall there, its status bar below the screen's
    // edge. The plot keeps 190, below which its axes lose their labels.
    // Below 500 px (a 1280 x 720 projector at a scale of 1.5 is 480 px tall) the window still
    // came out 497 px tall, its status bar below the edge: there the plot goes down to 160 px,
    // where it has fewer ticks and its side titles in short (refreshChart()).
    // The toolbars' rows count too: a 1024 x 768 projector at a scale of 1.5 is 683 x 512, where
    // they take three, and the window came out 536 px tall. So the sizes step down further while
    // the window's smallest layout is still taller than the screen.
    struct Heights {
        int stage;
        int plot;
    };
    static constexpr Heights steps[] = {
        {StageView::kMinimumHeight, PlotDock::kMinimumChartHeight}, {170, 190}, {120, 190}, {120, 160}, {90, 160}};
    m_fitHeight = availableHeight;
    std::size_t step = availableHeight < 500 ? 3 : availableHeight < 600 ? 2 : availableHeight < kSmallScreenHeight ? 1 : 0;
    for (;; ++step) {
        m_view->setMinimumHeight(steps[step].stage);
        m_plotDock->chartView()->setMinimumHeight(steps[step].plot);
        // Before the first show the toolbars' rows are not known yet (showEvent() fits again),
        // and laying the window out would size it.
        if (step + 1 == std::size(steps) || !isVisible())
            break;
        // The docks take their contents' new sizes in through posted layout requests.
        for (int round = 0; round < 3; ++round)
            QCoreApplication::sendPostedEvents(nullptr, QEvent::LayoutRequest);
        layout()->activate();
        if (minimumSizeHint().height() <= availableHeight)
            break;
    }
}

void MainWindow::readSettings()
{
    if (const QScreen *where = screen())
        fitScreenHeight(where->availableGeometry().height());
    QSettings settings;
    // A layout kept from a larger screen (the teacher's desk, then the classroom's projector)
    // would hide tools behind the toolbars' overflow and give the plot the room the stage needs:
    // on a smaller screen the window is laid out as on a first start.
    const QSize savedScreen = settings.value(QStringLiteral("window/screen")).toSize();
    const QSize screenNow = screen() ? screen()->availableGeometry().size() : QSize();
    const bool smallerScreen = savedScreen.isValid() && screenNow.isValid()
        && (screenNow.width() < savedScreen.width() || screenNow.height() < savedScreen.height());
    const QByteArray geometry = settings.value(QStringLiteral("window/geometry")).toByteArray();
    if (smallerScreen || geometry.isEmpty() || !restoreGeometryOnScreen(geometry))
        fitFirstWindow();
    // The docks and toolbars are laid out when the window is first shown, at its size: restored
    // before, the Parameters dock came back about 310 px wide whatever width it had been given.
    m_stateToRestore = smallerScreen ? QByteArray() : settings.value(QStringLiteral("window/state")).toByteArray();
    if (m_stateToRestore.isEmpty())
        m_firstLayout = true;
    updateFrameLabelsShown();
    m_vectorsAction->setChecked(settings.value(QStringLiteral("view/vectors"), true).toBool());
    m_trailsAction->setChecked(settings.value(QStringLiteral("view/trails"), false).toBool());
    m_plotDock->setTimeInSeconds(settings.value(QStringLiteral("plot/seconds"), false).toBool());
    m_plotDock->setKineticEnergyShown(settings.value(QStringLiteral("plot/kineticEnergy"), false).toBool());
    m_plotDock->setMomentumShown(settings.value(QStringLiteral("plot/momentum"), false).toBool());
    const int speed = settings.value(QStringLiteral("run/speedIndex"), kRealTimeSpeedIndex).toInt();
    if (speed >= 0 && speed < m_speedBox->count())
        m_speedBox->setCurrentIndex(speed);
}

bool MainWindow::restoreGeometryOnScreen(const QByteArray &saved)
{
    if (!restoreGeometry(saved))
        return false;
    const QScreen *where = screen();
    if (!where)
        return true;
    // A window saved maximized before it had ever had a size of its own (a first start on a
    // small screen) came back with a size of its own larger than the screen, which is what it
    // opens at where nothing maximizes it (no window manager), and what a window manager gives
    // it back when it is no longer maximized: 2099 x 1017 px on a 1280 x 720 projector at a
    // scale of 1.5, the docks and the status bar beyond the screen's edges, at every start
    // after the first (a helper's finding). One saved 20 px down came back with its status bar
    // below the screen's edge.
    const QRect room = where->availableGeometry();
    const bool maximized = isMaximized() || isFullScreen();
    const QRect placed = maximized ? normalGeometry() : geometry();
    if (placed.width() > room.width() || placed.height() > room.height() || (maximized && !room.contains(placed))) {
        setWindowState(Qt::WindowNoState);
        move(room.topLeft()); // laid out as on a first start, where that puts it
        return false;
    }
    if (!room.contains(placed)) {
        move(std::clamp(placed.x(), room.left(), room.right() + 1 - placed.width()),
             std::clamp(placed.y(), room.top(), room.bottom() + 1 - placed.height()));
    }
    return true;
}

void MainWindow::fitFirstWindow()
{
    // 1400 x 900 where it fits; on a smaller screen (a classroom projector at 1024 x 768) the
    // window takes the whole screen instead of opening with its docks beyond the edges.
    const QSize preferred(1400, 900);
    const QScreen *where = screen();
    const QSize available = where ? where->availableGeometry().size() : preferred;
    if (preferred.width() <= available.width() && preferred.height() <= available.height()) {
        resize(preferred);
        return;
    }
    resize(preferred.boundedTo(available));
    setWindowState(windowState() | Qt::WindowMaximized);
}

void MainWindow::writeSettings()
{
    QSettings settings;
    settings.setValue(QStringLiteral("window/geometry"), saveGeometry());
    settings.setValue(QStringLiteral("window/state"), saveState());
    if (screen())
        settings.setValue(QStringLiteral("window/screen"), screen()->availableGeometry().size());
    settings.setValue(QStringLiteral("view/vectors"), checkedBeforePreset(m_vectorsAction));
    settings.setValue(QStringLiteral("view/trails"), checkedBeforePreset(m_trailsAction));
    settings.setValue(QStringLiteral("plot/seconds"), m_plotDock->isTimeInSeconds());
    settings.setValue(QStringLiteral("plot/kineticEnergy"), m_plotDock->isKineticEnergyShown());
    settings.setValue(QStringLiteral("plot/momentum"), m_plotDock->isMomentumShown());
    settings.setValue(QStringLiteral("run/speedIndex"), m_speedBox->currentIndex());
}

void MainWindow::scheduleSettingsWrite()
{
    // Not before the kept layout is in place: written then, it would replace that layout with
    // the one the window has before its first show.
    if (m_settingsTimer && m_shownOnce && m_stateToRestore.isEmpty())
        m_settingsTimer->start();
}

void MainWindow::applyPresetView(const PresetView &view)
{
    // What the preset's lesson needs to be seen; the teacher's other choices stay.
    auto set = [this](QAction *action, std::optional<bool> value) {
        if (!value || action->isChecked() == *value)
            return;
        m_presetToggles.push_back({action, action->isChecked(), *value});
        action->setChecked(*value);
    };
    set(m_vectorsAction, view.vectors);
    set(m_trailsAction, view.trails);
    if (view.selectedMarble >= 0)
        m_view->selectMarble(view.selectedMarble);
}

bool MainWindow::replaceScene(const World &scene, const QString &fileName, const QString &presetTitle)
{
    // Another scene replaces the open one (a preset or a file), once the teacher has had the
    // chance to save changes: the run stops, nothing of the last scene stays selected (its
    // marble 3 is nothing to this one), and what a preset switched for its lesson is switched back.
    if (!maybeSave())
        return false;
    m_run->pause();
    hideBarMessage();
    m_document->resetScene(scene, fileName);
    // The last scene's changes were saved or discarded: nothing is left to recover, at once (a
    // crash before the autosave's next tick, up to 30 s on, offered the discarded changes back).
    m_autoSaver->discard();
    // After the reset: a discarded change's "not modified" came while the last scene's file
    // name still stood, and updateTitle() took the title away ('Preset "".' in the status bar).
    setPresetTitle(presetTitle);
    updateTitle();
    m_view->clearSelection();
    restoreViewBeforePreset();
    // The keys go to the stage (Right steps, Space plays): a number field that had the focus
    // kept it, with a stale part of its old text selected over the new scene's value.
    if (QWidget *focused = QApplication::focusWidget(); focused && focused != m_view && isAncestorOf(focused))
        m_view->setFocus(Qt::OtherFocusReason);
    return true;
}

void MainWindow::restoreViewBeforePreset()
{
    // Another scene opens: what the last preset switched is switched back, unless the teacher
    // switched it since (then it is the teacher's own choice).
    for (const PresetToggle &toggle : m_presetToggles) {
        if (toggle.action->isChecked() == toggle.set)
            toggle.action->setChecked(toggle.before);
    }
    m_presetToggles.clear();
}

bool MainWindow::checkedBeforePreset(const QAction *action) const
{
    // The teacher's setting, for the settings file: not one a preset made for its own lesson.
    for (const PresetToggle &toggle : m_presetToggles) {
        if (toggle.action == action && action->isChecked() == toggle.set)
            return toggle.before;
    }
    return action->isChecked();
}

QStringList MainWindow::recentFiles() const
{
    return QSettings().value(keyRecentFiles()).toStringList();
}

void MainWindow::addRecentFile(const QString &path)
{
    const QString absolute = QFileInfo(path).absoluteFilePath();
    QStringList files = recentFiles();
    files.removeAll(absolute);
    files.prepend(absolute);
    while (files.size() > kMaxRecentFiles)
        files.removeLast();
    setRecentFiles(files);
}

void MainWindow::setRecentFiles(const QStringList &files)
{
    QSettings().setValue(keyRecentFiles(), files);
    rebuildRecentMenu();
}

void MainWindow::rebuildRecentMenu()
{
    m_recentMenu->clear();
    const QStringList files = recentFiles();
    for (int k = 0; k < files.size(); ++k) {
        QAction *action = m_recentMenu->addAction(
            QStringLiteral("&%1 %2").arg(k + 1).arg(QFileInfo(files[k]).fileName()));
        action->setData(files[k]);
        action->setStatusTip(QDir::toNativeSeparators(files[k]));
        connect(action, &QAction::triggered, this, &MainWindow::openRecent);
    }
    m_recentMenu->setEnabled(!files.isEmpty());
}

void MainWindow::openRecent()
{
    const auto *action = qobject_cast<const QAction *>(sender());
    if (!action)
        return;
    const QString path = action->data().toString();
    // A file that is gone (deleted, renamed) leaves the list once its error was shown; one that
    // is there but cannot be read (a half-copied file, a folder not mounted right now) stays.
    if (!openFile(path) && !QFileInfo::exists(path)) {
        QStringList files = recentFiles();
        files.removeAll(path);
        setRecentFiles(files);
        showStatus(tr("%1 is gone: it was taken off File > Open Recent.").arg(QDir::toNativeSeparators(path)));
    }
}

namespace {

// Holds the run still while the window asks how to save, and plays it again after, unless told
// not to: the frame a question names is the frame saved. The run went on behind the questions,
// and "Save Frame 205" wrote frame 380 (a helper's finding, Save As in Pachinko's run).
class RunHeldWhileAsking {
public:
    explicit RunHeldWhileAsking(RunController *run)
        : m_run(run)
        , m_wasRunning(run->isRunning())
    {
        if (m_wasRunning)
            m_run->pause();
    }
    RunHeldWhileAsking(const RunHeldWhileAsking &) = delete;
    RunHeldWhileAsking &operator=(const RunHeldWhileAsking &) = delete;
    ~RunHeldWhileAsking()
    {
        if (m_wasRunning && m_resume)
            m_run->play();
    }
    /// The scene goes (closed, or replaced by another): its run is not played again.
    void keepStill() { m_resume = false; }

private:
    RunController *m_run;
    bool m_wasRunning;
    bool m_resume = true;
};

} // namespace

bool MainWindow::maybeSave()
{
    if (!m_document->isModified())
        return true;
    RunHeldWhileAsking held(m_run);
    const bool goOn = askToSaveChanges();
    if (goOn)
        held.keepStill(); // the caller closes the scene or replaces it
    return goOn;
}

bool MainWindow::askToSaveChanges()
{
    // At the run's start (frame 0, or where a save of the frame shown started it again) Save asks
    // nothing more: no frame to name.
    const std::int64_t frame = m_document->world().frame;
    switch (m_prompts->askSaveChanges(this, sceneName(), frame != m_document->startFrame() ? frame : 0,
                                      m_document->unsavableReason())) {
    case Prompts::SaveChoice::Save:
        return save();
    case Prompts::SaveChoice::Discard:
        return true;
    case Prompts::SaveChoice::Cancel:
        return false;
    }
    return false;
}

void MainWindow::newScene()
{
    // An empty table, as New gives in any program (it opened the four marbles, which a teacher
    // building a scene had first to delete); the presets are under File > Presets.
    if (!replaceScene(World(), QString(), QString()))
        return;
    updateTitle();
    showStatus(tr("A new, empty scene: place marbles and pins with Add Marble (M) and Add Pin (P), or open a "
                  "preset from File > Presets."));
}

bool MainWindow::openPreset(const QString &id)
{
    World scene;
    const QByteArray key = id.toUtf8();
    if (!makePreset(std::string_view(key.constData(), static_cast<std::size_t>(key.size())), scene)) {
        showStatus(tr("No preset named \"%1\".").arg(id));
        return false;
    }
    QString title;
    PresetView view;
    for (const PresetInfo &preset : presets()) {
        if (preset.id == key.toStdString()) {
            title = QString::fromStdString(preset.title);
            view = preset.view;
        }
    }
    if (!replaceScene(scene, QString(), title))
        return false;
    applyPresetView(view);
    updateTitle();
    showStatus(tr("Preset \"%1\".").arg(m_presetTitle));
    return true;
}

bool MainWindow::openArgument(const QString &argument)
{
    // "marbles preset:pachinko" said it could not open the file, where marbles-cli runs it.
    const QString prefix = QStringLiteral("preset:");
    if (argument.startsWith(prefix) && !QFileInfo::exists(argument))
        return openPreset(argument.mid(prefix.size()));
    return openFile(argument);
}

void MainWindow::open()
{
    QString directory;
    const QStringList recent = recentFiles();
    if (!m_document->fileName().isEmpty())
        directory = QFileInfo(m_document->fileName()).absolutePath();
    else if (!recent.isEmpty())
        directory = QFileInfo(recent.front()).absolutePath();
    const QString path = m_prompts->askOpenFileName(this, directory);
    if (!path.isEmpty())
        openFile(path);
}

bool MainWindow::openFile(const QString &path)
{
    // The file is read and checked before anything is asked or changed: an invalid file leaves
    // the open scene exactly as it was.
    World scene;
    QString error;
    SceneDocument::ReadNotes notes;
    if (!SceneDocument::readSceneFile(path, scene, &error, &notes)) {
        showStatus(error);
        m_prompts->showError(this, tr("Cannot open the scene"), error);
        return false;
    }
    if (!replaceScene(scene, QFileInfo(path).absoluteFilePath(), QString()))
        return false;
    addRecentFile(path);
    // Keys it does not read are said: a misspelt "Friction" had left the default in force without
    // a word (a helper's finding). Likely misspellings are asked to be put right; other keys (a
    // newer version's, a teacher's notes) only noted, as the file keeps them.
    QString opened = tr("Opened %1.").arg(QDir::toNativeSeparators(path));
    if (!notes.unusedKeys.isEmpty())
        opened += QLatin1Char(' ') + tr("Not used: %1").arg(notes.unusedKeys.join(QStringLiteral("; ")));
    showStatus(opened);
    if (notes.misspelt) {
        m_prompts->showError(this, tr("Keys not used"),
                             tr("The scene is open, but it holds keys that Marbles does not read, so their defaults "
                                "are in force:\n\n%1\n\nCorrect them in the file and open it again.")
                                 .arg(notes.unusedKeys.join(QLatin1Char('\n'))));
    }
    return true;
}

bool MainWindow::save()
{
    if (m_document->fileName().isEmpty())
        return saveAs();
    const RunHeldWhileAsking held(m_run);
    const std::optional<SceneDocument::SavedFrame> which = askSavedFrame(m_document->fileName());
    return which && saveFile(m_document->fileName(), *which);
}

std::optional<SceneDocument::SavedFrame> MainWindow::askSavedFrame(const QString &path)
{
    // Ctrl+S in the middle of a lesson's run had put that frame over the lesson's file, and the
    // status bar said so only afterwards (a helper's finding).
    const std::int64_t frame = m_document->world().frame;
    const std::int64_t start = m_document->startFrame();
    if (frame == start)
        return SceneDocument::SavedFrame::Shown;
    switch (m_prompts->askSaveFrame(this, QFileInfo(path).fileName(), frame, start, m_document->unsavableReason())) {
    case Prompts::SaveFrame::Now:
        return SceneDocument::SavedFrame::Shown;
    case Prompts::SaveFrame::Start:
        return SceneDocument::SavedFrame::Start;
    case Prompts::SaveFrame::Cancel:
        break;
    }
    return std::nullopt;
}

bool MainWindow::saveAs()
{
    const RunHeldWhileAsking held(m_run); // from the file's name: the frame is named after it
    QString suggestion = m_document->fileName();
    if (suggestion.isEmpty()) {
        const QStringList recent = recentFiles();
        const QString directory = recent.isEmpty() ? QDir::homePath() : QFileInfo(recent.front()).absolutePath();
        // A preset's own name ("pachinko-board.marbles.json", as its plot's exports are offered).
        const QString stem = sceneFileStem(m_presetTitle);
        suggestion = QDir(directory).filePath((stem.isEmpty() ? QStringLiteral("scene") : stem) + QStringLiteral(".marbles.json"));
    }
    const QString path = m_prompts->askSaveFileName(this, suggestion);
    if (path.isEmpty())
        return false;
    const std::optional<SceneDocument::SavedFrame> which = askSavedFrame(path);
    return which && saveFile(path, *which);
}

bool MainWindow::saveFile(const QString &path, SceneDocument::SavedFrame which)
{
    QString error;
    const std::int64_t start = m_document->startFrame();
    if (!m_document->saveFile(path, &error, which)) {
        showStatus(error);
        m_prompts->showError(this, tr("Cannot save the scene"), error);
        return false;
    }
    m_autoSaver->discard();
    addRecentFile(path);
    // A click's push waits for the next frame in the world; a file holds only scripted pushes.
    const World &world = m_document->world();
    const bool pushPending = which == SceneDocument::SavedFrame::Shown && m_document->pendingPushCount() > 0;
    // Saved mid-run, the file holds the scene as it is now, not the run's start: said, as a
    // teacher who saved at frame 36 reopened a different lesson without a word. (Short: a
    // 1600-px window's status bar had cut off its end.)
    const QString name = QDir::toNativeSeparators(path);
    QString text = tr("Saved %1").arg(name);
    if (which == SceneDocument::SavedFrame::Start && world.frame != start)
        text = tr("Saved %1 as at the start of its run, frame %2").arg(name).arg(start);
    else if (world.frame > 0)
        text = tr("Saved %1 at frame %2, where it opens as frame 0").arg(name).arg(world.frame);
    if (pushPending)
        text += tr(" (not the click's push still to act)"); // short: at 1600 px, comparing, it was cut off
    showStatus(text + QLatin1Char('.'));
    return true;
}

QString MainWindow::offerRecovery()
{
    if (!m_autoSaver->hasRecovery())
        return QString();
    const QString source = m_autoSaver->recoverySource();
    const QString preset = m_autoSaver->recoveryPresetTitle();
    const QString scene = !source.isEmpty()  ? tr("The scene %1 had unsaved changes.").arg(source)
                          : !preset.isEmpty() ? tr("The scene made from the preset \"%1\" had unsaved changes.").arg(preset)
                                              : tr("An untitled scene had unsaved changes.");
    const QString details = scene + QLatin1Char(' ') + tr("It comes back with every change, as at the start of its run.");
    if (m_prompts->askRecover(this, details)) {
        QString error;
        if (m_autoSaver->recover(&error)) {
            // Named as before the crash: its file, or its preset (not the preset opened at start).
            setPresetTitle(source.isEmpty() ? preset : QString());
            updateTitle();
            showStatus(tr("Recovered the autosaved scene. Save it to keep it."));
            return m_document->fileName();
        }
        // Recover was chosen, not Discard: the autosave is kept, out of the way (it was deleted).
        const QString kept = m_autoSaver->setAside();
        if (!kept.isEmpty())
            error += QLatin1String("\n\n") + tr("The autosave is kept as %1.").arg(QDir::toNativeSeparators(kept));
        m_prompts->showError(this, tr("Cannot recover the scene"), error);
        return QString();
    }
    m_autoSaver->discard();
    return QString();
}

// Space is Play / Pause, except on a control that Space works: a focused button or check box is
// pressed, a drop-down list opens (the shortcut took Space from them, so a teacher who tabbed to
// PNG... or Kinetic energy started the run instead). In the Undo History, Space still plays.
bool MainWindow::eventFilter(QObject *watched, QEvent *event)
{
    // A dock given another size by its splitter: the layout to keep changed.
    if (event->type() == QEvent::Resize && watched->parent() == this && qobject_cast<QDockWidget *>(watched))
        scheduleSettingsWrite();
    if (event->type() == QEvent::ShortcutOverride) {
        const auto *key = static_cast<QKeyEvent *>(event);
        const bool plainSpace = key->key() == Qt::Key_Space
            && (key->modifiers() & ~Qt::KeypadModifier) == Qt::NoModifier;
        if (plainSpace && (qobject_cast<QAbstractButton *>(watched) || qobject_cast<QComboBox *>(watched))) {
            event->accept(); // the control takes its key
            return true;
        }
        // Where the locale groups digits with a space (French: "1 500"), a number being typed
        // takes the space: Space took the "1" and played, and "500" went on into the field, two
        // edits without a word (a helper's finding). The field reads "1 500" as 1500 there (a
        // space is never a decimal mark). A field holding its value still plays.
        if (plainSpace) {
            auto *box = qobject_cast<QAbstractSpinBox *>(watched);
            const auto *field = dynamic_cast<const Refusing *>(box);
            if (field && field->typing() && groupsWithSpaces(box->locale())) {
                event->accept();
                return true;
            }
        }
        // Delete and Backspace in a read-only field (the Inspector's mass, worked out from the
        // radius) delete nothing: they had gone past it to Edit > Delete, and the marble went
        // (a re-tester's finding). An editable field takes them for its text.
        if ((key->key() == Qt::Key_Delete || key->key() == Qt::Key_Backspace)
            && (key->modifiers() & ~Qt::KeypadModifier) == Qt::NoModifier) {
            const auto *edit = qobject_cast<const QLineEdit *>(watched);
            const auto *box = edit ? qobject_cast<const QAbstractSpinBox *>(edit->parentWidget()) : qobject_cast<const QAbstractSpinBox *>(watched);
            if ((box && box->isReadOnly()) || (edit && edit->isReadOnly())) {
                event->accept();
                return true;
            }
        }
        // Esc in a number field puts back the number it holds and the keys on the stage (it
        // cleared the stage's selection, the Inspector's marble going with it, and left the
        // keys in the field: ] typed into it and 14 Tabs led back to the stage).
        // Esc in an open drop-down list (or any popup) closes it, and that only: it cleared the
        // stage's selection too, through Edit > Clear Selection (a re-tester's finding).
        if (key->key() == Qt::Key_Escape && QApplication::activePopupWidget()) {
            event->accept();
            return true;
        }
        if (key->key() == Qt::Key_Escape && key->modifiers() == Qt::NoModifier) {
            auto *widget = qobject_cast<QWidget *>(watched);
            QAbstractSpinBox *field = nullptr;
            for (QWidget *w = widget; w && !field; w = w->parentWidget())
                field = qobject_cast<QAbstractSpinBox *>(w);
            // A text field (the Inspector's name) likewise, its "kept" text back.
            auto *edit = field ? nullptr : qobject_cast<QLineEdit *>(watched);
            const bool number = field && isAncestorOf(field); // (isAncestorOf() stops at windows)
            const bool text = edit && edit->property("kept").isValid() && isAncestorOf(edit);
            if (number || text) {
                if (auto *real = qobject_cast<QDoubleSpinBox *>(field)) {
                    real->setValue(real->value());
                } else if (auto *whole = qobject_cast<QSpinBox *>(field)) {
                    whole->setValue(whole->value());
                } else if (edit) {
                    edit->setText(edit->property("kept").toString());
                    edit->setModified(false);
                }
                // The edit is called off: a refusal it left on show goes too (a name too long
                // stayed refused under the name Esc had put back).
                m_parametersDock->clearRefusal();
                m_inspectorDock->clearRefusal();
                m_view->setFocus(Qt::ShortcutFocusReason);
                event->accept();
                return true;
            }
            // From a drop-down list (closed), a button, a check box or a list, Esc takes the keys
            // back to the stage too: it had done so from number fields alone, and a teacher at the
            // keyboard found no way back from the Model box (a helper's finding).
            auto *combo = qobject_cast<QComboBox *>(watched);
            const bool control = (combo && !combo->view()->isVisible()) || qobject_cast<QAbstractButton *>(watched)
                || qobject_cast<QAbstractItemView *>(watched);
            if (control && widget != m_view && isAncestorOf(widget)) {
                m_view->setFocus(Qt::ShortcutFocusReason);
                event->accept();
                return true;
            }
        }
    }
    return QMainWindow::eventFilter(watched, event);
}

void MainWindow::showEvent(QShowEvent *event)
{
    QMainWindow::showEvent(event);
    if (m_shownOnce)
        return;
    m_shownOnce = true;
    if (!m_stateToRestore.isEmpty() && !restoreState(std::exchange(m_stateToRestore, QByteArray())))
        m_firstLayout = true;
    updateFrameLabelsShown();
    fitToolBars();
    if (m_fitHeight > 0) {
        fitScreenHeight(m_fitHeight); // with the toolbars in their rows
        // Maximized, and made taller than the screen by the sizes before (an X server without a
        // window manager keeps what the layout asked for), it comes back within it.
        if (isMaximized() && height() > m_fitHeight)
            resize(width(), std::max(m_fitHeight, minimumSizeHint().height()));
    }
    if (!m_firstLayout) {
        // A kept layout: a Parameters dock narrower than its fields (kept from a narrower window,
        // its fields cut off behind a sideways scroll bar) gets the width they need, as far as
        // the stage keeps its own.
        widenParametersToItsFields();
        return;
    }
    // First start (no saved layout): the stage gets most of the room, the plot a strip below it.
    // Dock sizes only apply once the window has its size, hence here and not in the constructor.
    m_firstLayout = false;
    resizeDocks({m_parametersDock, m_inspectorDock}, {350, 350}, Qt::Horizontal);
    resizeDocks({m_parametersDock, m_inspectorDock}, {560, 260}, Qt::Vertical);
    resizeDocks({m_plotDock}, {210}, Qt::Vertical);
}

void MainWindow::resizeEvent(QResizeEvent *event)
{
    QMainWindow::resizeEvent(event);
    // The window's width may come after its first show (-geometry 1024x700 was applied once the
    // toolbars had been laid out for 1400 px, and hid seven tools behind the overflow button),
    // or the teacher narrows it: the rows are laid out again.
    if (m_shownOnce && width() != m_toolBarsFitWidth)
        fitToolBars();
    // Widened again after it was narrowed, the window gave all its new width to the stage and
    // left the Parameters dock squeezed, its fields cut off (a projector tester's finding).
    if (m_shownOnce && event->oldSize().isValid() && event->size().width() > event->oldSize().width())
        QTimer::singleShot(0, this, &MainWindow::widenParametersToItsFields); // once the layout has its size
    scheduleSettingsWrite();
}

void MainWindow::moveEvent(QMoveEvent *event)
{
    QMainWindow::moveEvent(event);
    scheduleSettingsWrite();
}

void MainWindow::widenParametersToItsFields()
{
    const int wanted = m_parametersDock->fieldsWidth();
    if (m_parametersDock->isVisible() && !m_parametersDock->isFloating() && m_parametersDock->width() < wanted)
        resizeDocks({m_parametersDock}, {wanted}, Qt::Horizontal);
}

void MainWindow::fitToolBars()
{
    // On a narrow screen a toolbar that would not fit in its row goes to a new row, rather than
    // its tools behind an overflow menu; wide enough again, it goes back beside the others. On
    // every start, as a kept layout may come from a wider window, and on every change of width.
    const int width = isMaximized() && screen() ? screen()->availableGeometry().width() : this->width();
    m_toolBarsFitWidth = this->width();
    int row = 0;
    bool first = true;
    for (const QString &name : {QStringLiteral("fileToolBar"), QStringLiteral("runToolBar"),
                                QStringLiteral("compareToolBar"), QStringLiteral("toolsToolBar")}) {
        auto *bar = findChild<QToolBar *>(name);
        if (!bar || bar->isHidden() || toolBarArea(bar) != Qt::TopToolBarArea)
            continue;
        const int barWidth = bar->sizeHint().width();
        const bool breakBefore = !first && row + barWidth > width;
        if (!first && toolBarBreak(bar) != breakBefore) {
            if (breakBefore)
                insertToolBarBreak(bar);
            else
                removeToolBarBreak(bar);
        }
        if (breakBefore)
            row = 0;
        row += barWidth;
        first = false;
    }
}

void MainWindow::closeEvent(QCloseEvent *event)
{
    if (!maybeSave()) {
        event->ignore();
        return;
    }
    m_run->pause();
    m_settingsTimer->stop();
    writeSettings();
    // A clean exit: nothing to recover next time.
    m_autoSaver->discard();
    event->accept();
}

void MainWindow::togglePlay()
{
    hideBarMessage();
    m_run->toggle();
}

void MainWindow::stepForward()
{
    m_run->pause();
    // Past a frame that is no longer numbers there is nothing to show (a step went on to NaN,
    // a marble vanished and the status bar read "KE nan").
    if (!m_document->allFinite()) {
        showFrameStatus(tr("Frame %1 is not all finite numbers: there is nothing after it to show. Step back, or "
                           "lower the friction to 2 or less for the book model.")
                            .arg(m_document->world().frame));
        return;
    }
    m_document->advance(1);
}

QString MainWindow::leftPushText(std::int64_t left) const
{
    // The push clicked at the frame left is not the frame gone back to's (which has its own, if
    // any): said, as it went without a word (a helper's finding).
    return tr("Back to frame %1, without the push that was waiting at frame %2.").arg(m_document->world().frame).arg(left);
}

void MainWindow::stepBackward()
{
    m_run->pause();
    const bool pushWaiting = m_document->pendingPushCount() > 0;
    const std::int64_t left = m_document->world().frame;
    if (m_document->stepBack()) {
        hideBarMessage();
        if (pushWaiting)
            showFrameStatus(leftPushText(left));
        return;
    }
    // Where the keys go first, why after: a projector's narrow status bar cuts the end off.
    // (Short: a 1600-px window's bar cut its end off. A removal keeps the frames before it.) The
    // reason is the one that held: it had always said "10000 frames at most", where a 20,000-marble
    // scene's 256 MiB hold 219.
    const FrameHistory::Limit limit = m_document->history().lastLimit();
    const QString why = limit.frames == 0 ? tr("none kept before a marble added")
                        : limit.bytes
                            ? tr("its %1 MiB hold %2 frames of this scene")
                                  .arg(FrameHistory::kDefaultMaxBytes >> 20)
                                  .arg(limit.frames)
                            : tr("%1 frames at most").arg(limit.frames);
    showFrameStatus(tr("Frame %1 is not kept: Step Back reaches frame %2, Home frame %3 (%4).")
                        .arg(m_document->world().frame - 1)
                        .arg(m_document->world().frame - static_cast<std::int64_t>(m_document->history().size()))
                        .arg(m_document->startFrame())
                        .arg(why));
}

void MainWindow::rewindToStart()
{
    m_run->pause();
    const bool pushWaiting = m_document->pendingPushCount() > 0;
    const std::int64_t left = m_document->world().frame;
    if (m_document->rewind()) {
        hideBarMessage();
        QString text = pushWaiting && left != m_document->world().frame ? leftPushText(left)
                                                                         : tr("Back to frame %1.").arg(m_document->world().frame);
        // Those that acted went without a word: played again, the run went on without them (a
        // helper's finding).
        const std::vector<std::int64_t> &acted = m_document->pushesLeftByRewind();
        if (!acted.empty()) {
            // "0", "0 and 2", "0, 2 and 5", "0, 2, 5 …"
            QString frames;
            const std::size_t listed = std::min<std::size_t>(acted.size(), 3);
            for (std::size_t k = 0; k < listed; ++k) {
                if (k > 0)
                    frames += k + 1 == listed && acted.size() <= 3 ? tr(" and ") : QStringLiteral(", ");
                frames += QString::number(acted[k]);
            }
            if (acted.size() > 3)
                frames += QStringLiteral(" …");
            text += QLatin1Char(' ')
                + (acted.size() == 1
                       ? tr("The run goes on without the push clicked at frame %1: a click is not part of the scene.")
                       : tr("The run goes on without the pushes clicked at frames %1: clicks are not part of the scene."))
                      .arg(frames);
        }
        showFrameStatus(text);
    }
}

void MainWindow::onSpeedChosen(int index)
{
    if (index >= 0 && index < static_cast<int>(std::size(kSpeeds)))
        m_run->setSpeed(kSpeeds[index]);
    m_slowerAction->setEnabled(index > 0);
    m_fasterAction->setEnabled(index + 1 < m_speedBox->count());
}

void MainWindow::stepSpeed(int by)
{
    const int index = std::clamp(m_speedBox->currentIndex() + by, 0, m_speedBox->count() - 1);
    m_speedBox->setCurrentIndex(index);
    showStatus(tr("Run speed %1: one second of the scene takes %2 s.")
                   .arg(m_speedBox->currentText(), shownNumber(1.0 / kSpeeds[index], 'g', 3)));
}

void MainWindow::onRunningChanged(bool running)
{
    m_playAction->setText(running ? tr("&Pause") : tr("&Play"));
    m_playAction->setToolTip(withShortcut(m_playAction));
    m_playAction->setIcon(running ? themeIcon(QStringLiteral("media-playback-pause"), QStyle::SP_MediaPause)
                                  : themeIcon(QStringLiteral("media-playback-start"), QStyle::SP_MediaPlay));
    updateSlowLabel();
}

void MainWindow::onSimulationFailed(const QString &message)
{
    showBarMessage(message);
    showFrameStatus(message); // about this frame: stepping back leaves it
}

void MainWindow::tintPlottedMarbles()
{
    const QList<QPair<int, QColor>> colours = m_plotDock->stageColours();
    m_view->setMarbleTints(colours);
    m_compare->setTints(colours);
}

void MainWindow::onParamEdited(const QString &key, const QString &value)
{
    const QString error = m_document->setParam(key, value);
    if (!error.isEmpty()) {
        showStatus(error);
        m_parametersDock->setParams(m_document->world().params);
        return;
    }
    // A crowd from marbles-cli gen gives every marble its mass: the scale then changes nothing,
    // and a teacher watching the energy for its effect is told why.
    const World &world = m_document->world();
    if (key == QLatin1String("massScale") && world.marbleCount() > 0
        && std::all_of(world.info.begin(), world.info.end(), [](const MarbleInfo &info) { return info.hasMass; }))
        showStatus(tr("Every marble here has a mass of its own: the mass scale changes none of them (see the "
                      "Inspector's \u201cmass scale \u00d7 radius\u201d)."));
}

void MainWindow::onSceneChanged()
{
    m_parametersDock->setParams(m_document->world().params);
    m_plotDock->updateMarbleInfo(m_document->world());
    updateEditActions();
    updateStatistics();
    updateCompareControls();
}

void MainWindow::onSelectionChanged()
{
    const int marble = m_view->selectedMarble();
    m_inspectorDock->setMarble(marble);
    m_plotDock->setSelectedMarbles(marble >= 0 ? QList<int>{marble} : QList<int>{});
    updateEditActions();
}

void MainWindow::onToolChosen(QAction *action)
{
    if (action == m_marbleToolAction)
        m_view->setTool(StageView::Tool::AddMarble);
    else if (action == m_pinToolAction)
        m_view->setTool(StageView::Tool::AddPin);
    else
        m_view->setTool(StageView::Tool::Select);
}

void MainWindow::addMarbleHere()
{
    showStatus(m_view->addMarbleAt(m_view->contextPoint()));
}

void MainWindow::addPinHere()
{
    showStatus(m_document->addPin(StageView::placeAt(m_view->contextPoint())));
}

void MainWindow::onCompareChosen(QAction *action)
{
    const int data = action->data().toInt();
    if (data < 0)
        m_compare->stop();
    else
        m_compare->setModel(static_cast<ModelKind>(data));
}

void MainWindow::updateCompareControls()
{
    const ModelKind current = m_document->world().params.model;
    if (m_compare->isActive() && m_compare->model() == current) {
        // The scene now runs the compared model itself: nothing left to compare with.
        const std::string_view name = modelName(current);
        showStatus(tr("Comparison off: the scene now runs the %1 model itself.")
                       .arg(QString::fromUtf8(name.data(), static_cast<qsizetype>(name.size()))));
        m_compare->stop(); // emits modelChanged(), which comes back here
        return;
    }
    const int chosen = m_compare->isActive() ? static_cast<int>(m_compare->model()) : -1;
    const QSignalBlocker blocker(m_compareBox);
    m_compareBox->clear();
    // The exact and impulse models need a friction below 1 (the book's above it is its
    // instability on show): while it is higher they are not offered, as in the Model box.
    const bool damped = m_document->world().params.friction < 1.0;
    const auto runs = [damped](int data) { return data < 0 || data == static_cast<int>(ModelKind::Book) || damped; };
    // The comparison on show that cannot run says so in the box and its tip, not only in the
    // status bar: "Compare: exact" stood over a plot whose dashed lines had stopped.
    const bool paused = !runs(chosen);
    const QString needsDamping = tr("Needs friction below 1: lower the friction first.");
    auto *items = qobject_cast<QStandardItemModel *>(m_compareBox->model());
    for (QAction *action : m_compareGroup->actions()) {
        const int data = action->data().toInt();
        // The scene's own model is not offered: it would only ever show a gap of 0.
        action->setVisible(data < 0 || data != static_cast<int>(current));
        action->setChecked(data == chosen);
        const bool runnable = runs(data);
        action->setEnabled(runnable || data == chosen);
        action->setToolTip(runnable ? QString() : needsDamping);
        if (action->isVisible()) {
            const QString name = action->text().remove(QLatin1Char('&')).toLower();
            m_compareBox->addItem(paused && data == chosen ? tr("Compare: %1 (paused)").arg(name) : tr("Compare: %1").arg(name),
                                  data);
            if (items && !runnable) {
                QStandardItem *item = items->item(m_compareBox->count() - 1);
                item->setEnabled(data == chosen); // the comparison on show stays, its readout says why it waits
                item->setToolTip(needsDamping);
            }
        }
    }
    m_compareBox->setCurrentIndex(m_compareBox->findData(chosen));
    if (paused) {
        const std::string_view name = modelName(static_cast<ModelKind>(chosen));
        m_compareBox->setToolTip(tr("Paused: the %1 model needs friction below 1 (the scene's is %2). Lower the "
                                    "friction to run it again.")
                                     .arg(QString::fromUtf8(name.data(), static_cast<qsizetype>(name.size())))
                                     .arg(shownNumber(m_document->world().params.friction)));
    } else {
        m_compareBox->setToolTip(m_compareBoxToolTip);
    }
    QString plotted;
    if (m_compare->isActive()) {
        const std::string_view name = modelName(m_compare->model());
        plotted = QString::fromUtf8(name.data(), static_cast<qsizetype>(name.size()));
    }
    // A comparison chosen starts from the scene's current frame: that sample gets its totals
    // (its speeds come from the comparison's kept frames); the CSV's first row had none. Only
    // then: an edit takes the sample again itself (timelineEdited).
    if (plotted != m_plotDock->compareModel()) {
        m_plotDock->setCompareModel(plotted);
        if (m_compare->world())
            m_plotDock->resample(m_document->world(), m_compare->world());
    }
    updateCompareReadout();
}

void MainWindow::updateCompareReadout()
{
    m_inspectorDock->comparisonChanged();
    m_compareLabel->setFullText(m_compare->summary());
    m_compareLabel->setVisible(m_compare->isActive());
    m_compareLabel->setToolTip(m_compare->isActive() ? m_compare->summary() + QStringLiteral("\n\n") + m_compareToolTip
                                                      : m_compareToolTip);
}

void MainWindow::showBarMessage(const QString &text)
{
    m_messageText->setText(text);
    m_messageBar->show();
}

void MainWindow::hideBarMessage()
{
    m_messageText->clear();
    m_messageBar->hide();
}

QString MainWindow::barMessage() const
{
    return m_messageBar->isVisible() || !m_messageText->text().isEmpty() ? m_messageText->text() : QString();
}

void MainWindow::showStatus(const QString &text)
{
    if (!text.isEmpty())
        statusBar()->showMessage(text, 8000);
}

void MainWindow::showFrameStatus(const QString &text)
{
    showStatus(text);
    m_frameStatus = text;
    m_frameStatusAt = m_document->world().frame;
}

void MainWindow::expireFrameStatus()
{
    if (m_frameStatus.isEmpty() || m_document->world().frame == m_frameStatusAt)
        return;
    if (statusBar()->currentMessage() == m_frameStatus)
        statusBar()->clearMessage();
    m_frameStatus.clear();
}

QString MainWindow::sceneName() const
{
    return m_document->fileName().isEmpty() && !m_presetTitle.isEmpty() ? tr("Preset: %1").arg(m_presetTitle)
                                                                         : m_document->displayName();
}

void MainWindow::updateTitle()
{
    if (!m_document->fileName().isEmpty())
        setPresetTitle(QString());
    setWindowTitle(tr("%1[*] — Marbles").arg(sceneName()));
    setWindowModified(m_document->isModified());
    m_plotDock->setSceneName(sceneName());
    m_plotDock->setSceneEdited(m_document->isModified());
    m_plotDock->setSceneFile(m_document->fileName());
}

void MainWindow::setPresetTitle(const QString &title)
{
    m_presetTitle = title;
    m_autoSaver->setPresetTitle(title);
}

QString MainWindow::frameText() const
{
    return m_frameDisplay->text();
}

void MainWindow::updateFrameDisplay()
{
    const World &world = m_document->world();
    const double seconds = static_cast<double>(world.frame) * world.params.frameMs / 1000.0;
    m_frameDisplay->setText(tr("Frame %1   t = %2 s").arg(world.frame).arg(shownNumber(seconds, 'f', 2)));
    m_frameLabel->setText(tr("Frame %1").arg(world.frame));
    m_timeLabel->setText(tr("t = %1 s").arg(shownNumber(seconds, 'f', 3)));
}

void MainWindow::updateFrameLabelsShown()
{
    const auto *runBar = findChild<QToolBar *>(QStringLiteral("runToolBar"));
    const bool repeat = !runBar || runBar->isHidden();
    m_frameLabel->setVisible(repeat);
    m_timeLabel->setVisible(repeat);
}

void MainWindow::updateStatistics()
{
    const World &world = m_document->world();
    m_countLabel->setText(counted(world.marbleCount(), tr("marble"), tr("marbles")) + QStringLiteral(", ")
                          + counted(static_cast<qint64>(world.pins.size()), tr("pin"), tr("pins")));
    m_physicsLabel->setText(tr("physics %1 ms/frame").arg(shownNumber(m_document->physicsMsPerFrame(), 'f', 3)));
    const qint64 elapsed = m_statisticsClock.restart();
    const qint64 paints = m_view->paintCount();
    if (elapsed > 0)
        m_fpsLabel->setText(tr("display %1 fps").arg(static_cast<double>(paints - m_lastPaintCount) * 1000.0 / elapsed, 0, 'f', 0));
    m_lastPaintCount = paints;
    updateSlowLabel();
    // Plain numbers up to 1e12, as the plot's readout gives them ("KE 4.5862e+06" beside its
    // "1336500"), in the plot's unit of time: with its axis in seconds they had stayed per frame,
    // 2,500 times below its energy line at 20 ms a frame.
    const double f = m_plotDock->perSecond();
    auto energy = [f](const World &w) { return readableNumber(w.kineticEnergy() * f * f, 5); };
    auto momentum = [f](const World &w) {
        const Vec2 p = shownMomentum(w);
        return shownPair(readableNumber(p.x * f, 4), readableNumber(p.y * f, 4));
    };
    // With their units, which change with the plot's (the numbers jumped 2,500 times with nothing
    // in the bar to say why); while comparing, only in the tooltip (see below).
    const bool seconds = f != 1.0;
    const QString energyUnit = m_plotDock->energyUnit();
    const QString momentumUnit = m_plotDock->momentumUnit();
    m_energyLabel->setProperty("what", (seconds ? tr("Total kinetic energy, sum of m v² / 2, v in px/s (as the plot)")
                                                : tr("Total kinetic energy, sum of m v² / 2, v in px/frame"))
                                           + QStringLiteral(", ") + energyUnit);
    m_momentumLabel->setProperty("what", (seconds ? tr("Total momentum, sum of m v, v in px/s (as the plot)")
                                                  : tr("Total momentum, sum of m v, v in px/frame"))
                                             + QStringLiteral(", ") + momentumUnit);
    // While a comparison runs, both models' totals, each named: the scene's alone did not say
    // whose they were, and the comparison's (momentum kept where the book's is not) could only
    // be read off the plot.
    const World *compared = m_compare->world();
    // While comparing, the bar gives its room to both models' totals: the timing figures go (the
    // physics time is the scene's model's alone), and the totals were cut with "…" in a 1600-px
    // window on the Pachinko board.
    m_physicsLabel->setVisible(!compared);
    m_fpsLabel->setVisible(!compared);
    // So does the count of marbles and pins, which the stage shows: at 1024 x 768, a classroom
    // projector's, the totals were cut to "KE 90.912 (bo…" and "p = (72.68, 9.928) …".
    m_countLabel->setVisible(!compared);
    if (compared && compared->frame == world.frame) {
        // Two models' numbers and the comparison's gap fill a 1400-px bar: the units, which cut
        // the gap's summary short there, stay in the tooltip.
        const QString ours = QString::fromLatin1(modelName(world.params.model));
        const QString theirs = QString::fromLatin1(modelName(m_compare->model()));
        // Separated as numbers are in a list ("KE 4,913 (book); 8,6691 (exact)" in German).
        const QString sep = shownListSeparator();
        setTotal(m_energyLabel, tr("KE %1 (%2)%5%3 (%4)").arg(energy(world), ours, energy(*compared), theirs, sep));
        setTotal(m_momentumLabel, tr("p = %1 %2%5%3 %4").arg(momentum(world), ours, momentum(*compared), theirs, sep));
        return;
    }
    setTotal(m_energyLabel, tr("KE %1 %2").arg(energy(world), energyUnit));
    setTotal(m_momentumLabel, tr("p = %1 %2").arg(momentum(world), momentumUnit));
}

Vec2 MainWindow::shownMomentum(const World &world)
{
    // A component within the sum's rounding error of zero is zero: the exact model's momentum y
    // of marbles moving only across read "-4.441e-16" beside the book's "-0.4395". The error of a
    // sum of n terms is at most about n eps times the sum of their sizes.
    Vec2 p = world.momentum();
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
        // Past the doubles (the book model's blow-up): one m v at +inf and another at -inf made the
        // sum NaN, "p = (nan, inf)", where the true sum was finite (a helper's finding). Summed
        // with a wider exponent, it is the sum, or an infinity where the sum itself is beyond.
        long double sumX = 0.0L;
        long double sumY = 0.0L;
        for (int i = 0; i < world.marbleCount(); ++i) {
            sumX += static_cast<long double>(world.mass[i]) * world.velocity[i].x;
            sumY += static_cast<long double>(world.mass[i]) * world.velocity[i].y;
        }
        p = {static_cast<double>(sumX), static_cast<double>(sumY)};
    }
    double sizeX = 0.0;
    double sizeY = 0.0;
    for (int i = 0; i < world.marbleCount(); ++i) {
        sizeX += std::abs(world.mass[i] * world.velocity[i].x);
        sizeY += std::abs(world.mass[i] * world.velocity[i].y);
    }
    // Only where the sizes are finite: past the doubles (the book model's blow-up, m v beyond
    // 1.8e308) the bound was infinite too, and a momentum of inf read "p = (0, 0)" beside
    // "KE inf" (a helper's finding).
    const double bound = world.marbleCount() * std::numeric_limits<double>::epsilon();
    const auto shown = [bound](double component, double size) {
        return std::isfinite(size) && std::abs(component) <= bound * size ? 0.0 : component;
    };
    return {shown(p.x, sizeX), shown(p.y, sizeY)};
}

void MainWindow::setTotal(ElidingLabel *label, const QString &text)
{
    label->setFullText(text);
    label->setToolTip(label->property("what").toString() + QStringLiteral("\n") + text);
}

void MainWindow::updateSlowLabel()
{
    const bool slow = m_run->isFallingBehind();
    if (slow)
        m_slowLabel->setText(tr("slowed to %1×").arg(shownNumber(m_run->achievedSpeed(), 'f', 2)));
    m_slowLabel->setVisible(slow);
}

void MainWindow::updateEditActions()
{
    m_deleteAction->setEnabled(m_view->selectionKind() != StageView::SelectionKind::None);
    // Enabled past the first frame even when the frame before is not kept: Left then says why
    // it stops there (greyed out, it did nothing and said nothing).
    m_stepBackAction->setEnabled(m_document->canStepBack() || m_document->world().frame != m_document->startFrame());
    m_rewindAction->setEnabled(m_document->world().frame != m_document->startFrame() || m_document->canStepBack());
}

} // namespace marbles
