#pragma once

#include "core/presets.h"
#include "ui/scenedocument.h"

#include <QElapsedTimer>
#include <QKeySequence>
#include <QList>
#include <QMainWindow>
#include <QStringList>

#include <memory>
#include <optional>
#include <vector>

class QAction;
class QActionGroup;
class QComboBox;
class QDialog;
class QLabel;
class QMenu;
class QTimer;
class QUndoView;

namespace marbles {

class AutoSaver;
class ElidingLabel;
class CompareRun;
class InspectorDock;
class ParametersDock;
class PlotDock;
class Prompts;
class RunController;
class SceneDocument;
class StageView;

/// The application window: the stage in the middle, the Parameters, Inspector, History and Plot
/// docks around it, the run controls in the toolbar, and the numbers that matter in the status bar.
/// It opens on the chapter's four marbles.
class MainWindow : public QMainWindow {
    Q_OBJECT

public:
    /// Most recent files remembered.
    static constexpr int kMaxRecentFiles = 8;
    /// Below this available screen height (px) the stage and the plot may be smaller than usual.
    static constexpr int kSmallScreenHeight = 720;
    /// Time from the last change to a setting to its writing, ms (scheduleSettingsWrite()).
    static constexpr int kSettingsWriteDelayMs = 1000;
    /// Sets the stage's and the plot's smallest heights for a screen `availableHeight` px tall
    /// (done at start for the window's screen): smaller below kSmallScreenHeight.
    void fitScreenHeight(int availableHeight);
    /// Redo's keys: Ctrl+Shift+Z and Ctrl+Y, then the platform's own Redo keys (`platformRedo`)
    /// that are not already there. A key listed twice would be an ambiguous shortcut,
    /// which Qt ignores.
    static QList<QKeySequence> redoShortcuts(const QList<QKeySequence> &platformRedo);
    /// Zoom In's keys: the platform's (`platformZoomIn`, Ctrl++), then Ctrl+= unless listed: on
    /// most keyboards + is a shifted =, and Ctrl+= (the same key without Shift) zooms in
    /// elsewhere too.
    static QList<QKeySequence> zoomInShortcuts(const QList<QKeySequence> &platformZoomIn);

    /// The window, showing the default preset. Questions go to default Qt dialogs until setPrompts().
    explicit MainWindow(QWidget *parent = nullptr);
    ~MainWindow() override;

    /// Replaces the dialogs the window uses to ask questions (tests install scripted answers).
    void setPrompts(std::unique_ptr<Prompts> prompts);

    /// Opens a scene file: an invalid file shows the loader's message and leaves the scene as it
    /// was; unsaved changes are asked about first. Returns true when the file was opened.
    bool openFile(const QString &path);
    /// Opens what the command line names: a scene file, or "preset:ID" (as marbles-cli reads it)
    /// when no file of that name exists. Returns true when it was opened.
    bool openArgument(const QString &argument);
    /// Saves the scene to `path` atomically, at the frame shown or as at the start of its run;
    /// false (with a message) on failure.
    bool saveFile(const QString &path, SceneDocument::SavedFrame which);
    /// Replaces the scene with preset `id` (unsaved changes are asked about first).
    bool openPreset(const QString &id);
    /// Offers to recover an autosaved scene left by a session that did not end cleanly. Returns
    /// the file the recovered scene was made from ("" when nothing was recovered or the scene
    /// had no file).
    QString offerRecovery();

    /// The document (owned by the window).
    SceneDocument *document() const { return m_document; }
    /// The stage view.
    StageView *stageView() const { return m_view; }
    /// The run loop.
    RunController *runController() const { return m_run; }
    /// The second model run beside the document's (Simulation > Compare With).
    CompareRun *compareRun() const { return m_compare; }
    /// The Parameters dock.
    ParametersDock *parametersDock() const { return m_parametersDock; }
    /// The Plot dock.
    PlotDock *plotDock() const { return m_plotDock; }
    /// The Inspector dock.
    InspectorDock *inspectorDock() const { return m_inspectorDock; }
    /// The autosave.
    AutoSaver *autoSaver() const { return m_autoSaver; }
    /// Recent files, newest first.
    QStringList recentFiles() const;
    /// The text of the frame and time display in the toolbar.
    QString frameText() const;
    /// The message shown in the message bar above the stage ("" when hidden).
    QString barMessage() const;

    /// The scene's momentum as the status bar gives it: a component within the sum's rounding
    /// error of zero is zero.
    static Vec2 shownMomentum(const World &world);

protected:
    bool eventFilter(QObject *watched, QEvent *event) override;
    void showEvent(QShowEvent *event) override;
    void resizeEvent(QResizeEvent *event) override;
    void moveEvent(QMoveEvent *event) override;
    void closeEvent(QCloseEvent *event) override;

private:
    void createActions();
    void createMenus();
    void createToolBars();
    void createDocks();
    void createStatusBar();
    /// Toolbar buttons' tips name their keys ("Play (Space)").
    void addShortcutsToToolTips();
    /// The plotted marbles (and their ghosts) drawn in their lines' colours.
    void tintPlottedMarbles();
    void readSettings();
    void writeSettings();
    /// Writes the settings a moment after the last change to them (a toggle, a dock moved, the
    /// window resized), so that a crash or a power cut keeps them; closing writes them at once.
    void scheduleSettingsWrite();

    /// Asks, for a modified scene about to be closed or replaced, whether to save it (with the run
    /// held still while it asks); false: the scene stays (cancelled, or the save failed).
    bool maybeSave();
    bool askToSaveChanges();
    void newScene();
    void open();
    bool save();
    bool saveAs();
    /// Which frame a save writes: in the middle of a run the user is asked; none when cancelled.
    std::optional<SceneDocument::SavedFrame> askSavedFrame(const QString &path);
    void openRecent();
    void addRecentFile(const QString &path);
    /// Stores the recent files' list (newest first) and rebuilds File > Open Recent from it.
    void setRecentFiles(const QStringList &files);
    void rebuildRecentMenu();

    void togglePlay();
    void stepForward();
    void stepBackward();
    void rewindToStart();
    void onSpeedChosen(int index);
    /// Moves the run speed `by` steps along the speed box, within its ends, and says so.
    void stepSpeed(int by);
    void onRunningChanged(bool running);
    void onSimulationFailed(const QString &message);
    void onParamEdited(const QString &key, const QString &value);
    void onSceneChanged();
    void onSelectionChanged();
    void onToolChosen(QAction *action);
    void addMarbleHere();
    void addPinHere();
    void onCompareChosen(QAction *action);
    void updateCompareControls();
    void updateCompareReadout();

    void showBarMessage(const QString &text);
    void hideBarMessage();
    void showStatus(const QString &text);
    /// Shows a status message about the current frame, cleared when another frame is shown
    /// ("Back to frame 0" or a push still to act would read as the state of a later frame).
    void showFrameStatus(const QString &text);
    /// "Back to frame F, without the push that was waiting at frame `left`." (Step Back, Home).
    QString leftPushText(std::int64_t left) const;
    /// Clears a showFrameStatus() message once the frame is not the one it was about.
    void expireFrameStatus();
    /// The open scene's name, as the title bar and the save prompt show it.
    QString sceneName() const;
    /// The preset the open, untitled scene came from (also what its autosave is named by).
    void setPresetTitle(const QString &title);
    void updateTitle();
    void updateFrameDisplay();
    void updateStatistics();
    void updateSlowLabel();
    /// Shows a total (`label`, the energy's or the momentum's) in the status bar, with its whole text in the tip.
    static void setTotal(ElidingLabel *label, const QString &text);
    void updateFrameLabelsShown();
    void fitFirstWindow();
    /// restoreGeometry(), kept only where the window it gives fits the screen's free area: moved
    /// into it if it lies partly outside; false (the state cleared) if it is larger.
    bool restoreGeometryOnScreen(const QByteArray &saved);
    /// Breaks the toolbars into rows where one would not fit beside the last (on every start).
    void fitToolBars();
    /// A Parameters dock narrower than its fields gets the width they need, as far as the stage
    /// keeps its own.
    void widenParametersToItsFields();
    void showKeysAndMouse();
    void updateEditActions();
    /// Asks to save changes, then opens `scene` in place of the open one; false if cancelled.
    bool replaceScene(const World &scene, const QString &fileName, const QString &presetTitle);
    void applyPresetView(const PresetView &view);
    void restoreViewBeforePreset();
    bool checkedBeforePreset(const QAction *action) const;

    SceneDocument *m_document = nullptr;
    StageView *m_view = nullptr;
    RunController *m_run = nullptr;
    CompareRun *m_compare = nullptr;
    AutoSaver *m_autoSaver = nullptr;
    std::unique_ptr<Prompts> m_prompts;
    QString m_presetTitle;
    bool m_firstLayout = false;
    bool m_shownOnce = false;
    QTimer *m_settingsTimer = nullptr; ///< single shot: scheduleSettingsWrite()'s delay
    QString m_compareBoxToolTip; ///< the Compare box's tooltip while its comparison can run
    int m_toolBarsFitWidth = -1; ///< the width fitToolBars() last laid the toolbars out for
    int m_fitHeight = 0;         ///< the screen height fitScreenHeight() last fitted the window to
    QByteArray m_stateToRestore; // the kept layout, restored when the window is first shown
    bool m_warnedNoAutosave = false;
    /// A toggle a preset set for its lesson (PresetView): the teacher's own setting before it,
    /// given back when another scene opens (and saved in its place) unless changed meanwhile.
    struct PresetToggle {
        QAction *action = nullptr;
        bool before = false;
        bool set = false;
    };
    std::vector<PresetToggle> m_presetToggles;

    ParametersDock *m_parametersDock = nullptr;
    PlotDock *m_plotDock = nullptr;
    InspectorDock *m_inspectorDock = nullptr;
    QDockWidget *m_historyDock = nullptr;

    QAction *m_newAction = nullptr;
    QAction *m_openAction = nullptr;
    QAction *m_saveAction = nullptr;
    QAction *m_saveAsAction = nullptr;
    QAction *m_exportCsvAction = nullptr;
    QAction *m_exportPngAction = nullptr;
    QAction *m_quitAction = nullptr;
    QAction *m_undoAction = nullptr;
    QAction *m_redoAction = nullptr;
    QAction *m_deleteAction = nullptr;
    QActionGroup *m_toolGroup = nullptr;
    QAction *m_selectToolAction = nullptr;
    QAction *m_marbleToolAction = nullptr;
    QAction *m_pinToolAction = nullptr;
    QAction *m_addMarbleHereAction = nullptr;
    QAction *m_addPinHereAction = nullptr;
    QAction *m_playAction = nullptr;
    QAction *m_stepAction = nullptr;
    QAction *m_stepBackAction = nullptr;
    QAction *m_rewindAction = nullptr;
    QAction *m_slowerAction = nullptr;
    QAction *m_fasterAction = nullptr;
    QAction *m_nextMarbleAction = nullptr;
    QAction *m_clearSelectionAction = nullptr;
    QAction *m_previousMarbleAction = nullptr;
    QList<QAction *> m_pushActions; // Shift+arrows: push the selected marble
    QAction *m_fitAction = nullptr;
    QAction *m_zoomInAction = nullptr;
    QAction *m_zoomOutAction = nullptr;
    QAction *m_vectorsAction = nullptr;
    QAction *m_trailsAction = nullptr;
    QMenu *m_recentMenu = nullptr;
    QMenu *m_presetMenu = nullptr;
    QMenu *m_viewMenu = nullptr;
    QDialog *m_keysDialog = nullptr; // Help > Keyboard and Mouse, made on first use
    QComboBox *m_speedBox = nullptr;
    QActionGroup *m_compareGroup = nullptr; ///< None, book, exact, impulse; data: -1 or the ModelKind
    QMenu *m_compareMenu = nullptr;
    QComboBox *m_compareBox = nullptr;
    ElidingLabel *m_compareLabel = nullptr;
    QString m_compareToolTip; // what the readout means (its tool tip, under the readout's text)
    QString m_frameStatus;            // the showFrameStatus() message on show (empty: none)
    std::int64_t m_frameStatusAt = 0; // the frame it is about

    QWidget *m_messageBar = nullptr;
    QLabel *m_messageText = nullptr;
    QLabel *m_frameDisplay = nullptr;
    QLabel *m_frameLabel = nullptr;
    QLabel *m_timeLabel = nullptr;
    QLabel *m_countLabel = nullptr;
    QLabel *m_physicsLabel = nullptr;
    QLabel *m_fpsLabel = nullptr;
    QLabel *m_slowLabel = nullptr; // shown while the run cannot keep up with its speed
    ElidingLabel *m_energyLabel = nullptr;   // both models' totals while comparing: long, cut
    ElidingLabel *m_momentumLabel = nullptr; // with "…" where the bar has no room for them
    QTimer *m_statisticsTimer = nullptr;
    qint64 m_lastPaintCount = 0;
    QElapsedTimer m_statisticsClock;
};

} // namespace marbles
