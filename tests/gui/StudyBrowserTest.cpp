// GUI tests of the study browser and the PACS panel under Xvfb (Qt Test): a PACS round trip
// against a real Orthanc (C-FIND, C-GET and C-MOVE into the browser), 4D DICOM and NIfTI series
// opened volume by volume, the browser's filters, and a series without geometry said so.
// Screenshots under <build>/test-artifacts/gui/.
#include <QApplication>
#include <QComboBox>
#include <QDir>
#include <QDockWidget>
#include <QElapsedTimer>
#include <QLineEdit>
#include <QMenu>
#include <QMessageBox>
#include <QMouseEvent>
#include <QPushButton>
#include <QSettings>
#include <QFile>
#include <QtMath>
#include <QSpinBox>
#include <QStatusBar>
#include <QTimer>
#include <QSignalSpy>
#include <QTest>
#include <QTreeWidget>
#include <QTreeWidgetItemIterator>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/octree/OctreeBuilder.h"
#include "core/volume/PhantomVoxelSource.h"
#include "dicom/DicomSeriesWriter.h"
#include "dicom/IncomingStore.h"
#include "dicom/PacsSettings.h"
#include "tests/support/PacsPeer.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"
#include "tests/gui/GuiTestSupport.h"
#include "ui/JobManager.h"
#include "ui/MainWindow.h"
#include "ui/PacsNodeDialog.h"
#include "ui/PacsPanel.h"
#include "ui/SliceView.h"
#include "ui/StudyBrowser.h"
#include "core/base/Error.h"
#include "ui/VolumeView.h"

using namespace hvx;

namespace {
using test::writeSeries;
}  // namespace

class StudyBrowserTest : public QObject, test::GuiFixture {
    Q_OBJECT

private slots:
    void initTestCase() { open(); }

    void pacsRoundTripAgainstOrthanc() {
        test::PacsPeer peer(test::PacsPeer::Kind::Orthanc);
        peer.start();
        peer.seed(writeSeries(dir_.file("pacs-series"), "PACS^ROUNDTRIP", 5));
        peer.settings().save(dir_.file("pacs.json"));
        auto* pacs = window_->pacs();
        pacs->reloadSettings();
        pacs->nodes()->setCurrentText("peer");
        QTest::keyClicks(pacs->patientField(), "PACS*");
        QTest::mouseClick(pacs->findChild<QPushButton*>("pacsSearch"), Qt::LeftButton);
        QTRY_COMPARE_WITH_TIMEOUT(pacs->results()->topLevelItemCount(), 1, 30000);
        QVERIFY(pacs->results()->topLevelItem(0)->text(0).contains("PACS ROUNDTRIP"));
        pacs->results()->topLevelItem(0)->setSelected(true);
        auto* pacsDock = window_->findChild<QDockWidget*>("pacsDock");
        QVERIFY(pacsDock);
        pacsDock->raise();
        saveArtifact("pacs-search.png");  // the README's first steps: find a study
        window_->findChild<QDockWidget*>("studiesDock")->raise();
        QSignalSpy retrieved(pacs, &ui::PacsPanel::retrieved);
        QTest::mouseClick(pacs->findChild<QPushButton*>("pacsRetrieve"), Qt::LeftButton);
        QTRY_COMPARE_WITH_TIMEOUT(retrieved.count(), 1, 120000);
        bool listed = false;
        auto* tree = window_->browser()->tree();
        for (int i = 0; i < tree->topLevelItemCount(); ++i) listed |= tree->topLevelItem(i)->text(0).contains("PACS ROUNDTRIP");
        QVERIFY2(listed, "the retrieved study appears in the study browser");

        // C-MOVE, as a node set to move in its dialog is saved: the peer sends the study to the
        // storage SCP the retrieve starts on the local port, and the study is filed from there.
        const auto filed = [dir = peer.settings().local.storageDir] {  // files in the storage folder
            std::size_t n = 0;
            for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) n += e.is_regular_file() ? 1 : 0;
            return n;
        };
        const std::size_t before = filed();
        const auto moved = writeSeries(dir_.file("pacs-moved"), "PACS^MOVED", 9, "20231115");
        peer.seed(moved);
        auto moving = peer.settings();
        moving.nodes[0].retrieve = dicom::RetrieveMethod::Move;
        moving.save(dir_.file("pacs.json"));
        pacs->reloadSettings();
        pacs->nodes()->setCurrentText("peer");
        pacs->patientField()->clear();
        QTest::keyClicks(pacs->patientField(), "PACS^MOVED");
        QTest::mouseClick(pacs->findChild<QPushButton*>("pacsSearch"), Qt::LeftButton);
        QTRY_COMPARE_WITH_TIMEOUT(pacs->results()->topLevelItemCount(), 1, 30000);
        pacs->results()->topLevelItem(0)->setSelected(true);
        QTest::mouseClick(pacs->findChild<QPushButton*>("pacsRetrieve"), Qt::LeftButton);
        QTRY_COMPARE_WITH_TIMEOUT(retrieved.count(), 2, 120000);
        QVERIFY2(retrieved.last().first().toString().contains("1 series retrieved"),
                 qPrintable(retrieved.last().first().toString()));
        QCOMPARE(filed() - before, moved.size());  // what the peer pushed to the storage SCP
        QTreeWidgetItem* movedRow = nullptr;
        for (int i = 0; i < tree->topLevelItemCount(); ++i)
            if (tree->topLevelItem(i)->text(0).contains("PACS MOVED")) movedRow = tree->topLevelItem(i);
        QVERIFY2(movedRow && movedRow->childCount() == 1, "the moved study is in the browser");
        QCOMPARE(movedRow->child(0)->text(3), QString::number(moved.size()));  // every image filed
        // A wrong port gives plain words.
        auto s = peer.settings();
        s.nodes[0].port = std::uint16_t(peer.dicomPort() + 1000);
        s.save(dir_.file("pacs.json"));
        pacs->reloadSettings();
        pacs->nodes()->setCurrentText("peer");
        pacs->search();
        QTRY_VERIFY_WITH_TIMEOUT(!pacs->errorText().isEmpty() && !pacs->errorText().startsWith("Searching"), 60000);
        QVERIFY2(pacs->errorText().contains("port", Qt::CaseInsensitive), qPrintable(pacs->errorText()));
        saveArtifact("pacs.png");

        // The node dialog: typed values, Echo with them (the wrong port, then the right one),
        // and an AE title that cannot be longer than DICOM's 16 characters.
        ui::PacsNodeDialog dialog(peer.settings(), s.nodes[0]);
        dialog.show();
        QVERIFY(QTest::qWaitForWindowExposed(&dialog));
        QVERIFY2(dialog.echo().contains("port", Qt::CaseInsensitive), "the echo uses the typed (wrong) port");
        auto* port = dialog.findChild<QSpinBox*>();
        QVERIFY(port);
        port->selectAll();
        QTest::keyClicks(port, QString::number(peer.dicomPort()));
        QCOMPARE(port->value(), int(peer.dicomPort()));
        QVERIFY2(dialog.echo().contains("Echo succeeded"), qPrintable(dialog.echo()));
        QLineEdit* ae = nullptr;
        for (auto* e : dialog.findChildren<QLineEdit*>())
            if (e->text() == QString::fromStdString(peer.aeTitle())) ae = e;
        QVERIFY(ae);
        ae->selectAll();
        QTest::keyClicks(ae, "A_TITLE_LONGER_THAN_SIXTEEN");
        QCOMPARE(dialog.node().aeTitle, std::string("A_TITLE_LONGER_T"));
        QVERIFY2(dialog.echo().contains("A_TITLE_LONGER_T"), "a wrong called AE title is named in the answer");
        // The same dialog makes a DICOMweb node: its own fields, and an echo that is a QIDO-RS
        // search (here at a port nobody listens on: words, not a hang).
        auto* kind = dialog.findChild<QComboBox*>("nodeKind");
        auto* url = dialog.findChild<QLineEdit*>("nodeUrl");
        QVERIFY(kind && url);
        QVERIFY(!url->isVisible());
        kind->setCurrentIndex(1);
        QVERIFY(url->isVisible());
        QVERIFY(!port->isVisible());
        QTest::keyClicks(url, "http://127.0.0.1:" + QString::number(test::freePort()) + "/dicom-web");
        QCOMPARE(dialog.node().kind, dicom::NodeKind::DicomWeb);
        QVERIFY2(dialog.echo().contains("cannot connect"), qPrintable(dialog.echo()));
        url->setText("pacs:8042");
        QVERIFY_THROWS_EXCEPTION(core::Error, dialog.node());
        dialog.close();
    }

    // A 4D series (dual echo, written by pydicom) lists one row per volume with what varies;
    // double-clicking a volume's row opens that volume.
    void fourDimensionalSeriesListsItsVolumesAndOpensOne() {
        const auto r = test::runCommand("/usr/bin/python3 " HVX_SOURCE_DIR "/tests/support/dicom_cases.py " +
                                        dir_.file("cases"));
        QVERIFY2(r.exitCode == 0, r.output.c_str());
        QSignalSpy imported(window_->browser(), &ui::StudyBrowser::imported);
        window_->browser()->importPaths({QString::fromStdString(dir_.file("cases/echo"))});
        QTRY_COMPARE_WITH_TIMEOUT(imported.count(), 1, 60000);
        auto* tree = window_->browser()->tree();
        QTreeWidgetItem* second = nullptr;
        QStringList rows;
        for (QTreeWidgetItemIterator it(tree); *it; ++it)
            if ((*it)->text(0).startsWith("#")) {
                rows << (*it)->text(0);
                if ((*it)->text(0).contains("echo 2 (TE 20 ms)")) second = *it;
            }
        QCOMPARE(rows, (QStringList{"#1 echo 1 (TE 10 ms)", "#2 echo 2 (TE 20 ms)"}));
        QVERIFY(second);
        tree->scrollToItem(second);
        const QRect rect = tree->visualItemRect(second);
        QTest::mouseClick(tree->viewport(), Qt::LeftButton, {}, rect.center());
        QTest::mouseDClick(tree->viewport(), Qt::LeftButton, {}, rect.center());
        QVERIFY(window_->jobs()->waitIdle(120000));
        QTRY_VERIFY_WITH_TIMEOUT(window_->openLabel().contains("echo 2") && !window_->openLabel().endsWith("(preview)"),
                                 10000);
        // Echo 2's pixels are 1000 above echo 1's (tests/support/dicom_cases.py): the view shows them.
        QVERIFY2(window_->slice(0)->windowCentre() > 900.0, qPrintable(QString::number(window_->slice(0)->windowCentre())));
        saveArtifact("browser-4d-series.png");
    }

    // The browser's filters, typed and picked as a user does: a name pattern (Enter), a modality,
    // a date range; each shows exactly the studies that match, and clearing them shows all again.
    void browserFiltersByNameModalityAndDate() {
        auto* browser = window_->browser();
        auto* tree = browser->tree();
        browser->refresh();
        const int all = tree->topLevelItemCount();
        QVERIFY2(all >= 3, qPrintable(QString::number(all)));  // PACS^ROUNDTRIP, PACS^MOVED, the pydicom cases
        const auto patients = [&] {
            QStringList names;
            for (int i = 0; i < tree->topLevelItemCount(); ++i) names << tree->topLevelItem(i)->text(0);
            return names;
        };
        QLineEdit *text = nullptr, *from = nullptr, *to = nullptr;
        for (auto* e : browser->findChildren<QLineEdit*>()) {
            if (e->placeholderText().startsWith("Patient")) text = e;
            if (e->placeholderText().startsWith("from")) from = e;
            if (e->placeholderText().startsWith("to")) to = e;
        }
        QVERIFY(text && from && to);
        QTest::keyClicks(text, "PACS*");
        QTest::keyClick(text, Qt::Key_Return);
        QCOMPARE(patients().size(), 2);  // PACS^ROUNDTRIP and PACS^MOVED, from the PACS test
        QVERIFY2(patients().join(",").contains("PACS ROUNDTRIP") && patients().join(",").contains("PACS MOVED"),
                 qPrintable(patients().join(", ")));
        text->clear();
        QTest::keyClicks(text, "*ROUND*");
        QTest::keyClick(text, Qt::Key_Return);
        QCOMPARE(patients().size(), 1);
        QVERIFY2(patients().first().contains("PACS ROUNDTRIP"), qPrintable(patients().join(", ")));
        text->clear();
        auto* modality = browser->findChild<QComboBox*>();
        QVERIFY(modality);
        modality->setFocus();
        modality->setCurrentText("MR");
        emit modality->activated(modality->currentIndex());
        QVERIFY(tree->topLevelItemCount() >= 1);
        for (QTreeWidgetItemIterator it(tree); *it; ++it)
            if ((*it)->parent() && !(*it)->parent()->parent())  // a study row: its modalities
                QVERIFY2((*it)->text(2).contains("MR"), qPrintable((*it)->text(0) + " " + (*it)->text(2)));
        modality->setCurrentText("Any");
        QTest::keyClicks(from, "99990101");  // the future: nothing
        QTest::keyClick(text, Qt::Key_Return);
        QCOMPARE(tree->topLevelItemCount(), 0);
        QTest::keyClicks(from, "x");  // the date field takes digits only
        QCOMPARE(from->text(), QString("99990101"));
        // A range that keeps some: November 2023 holds the moved study alone (20231115); one day,
        // 1 March 2024, holds the pydicom cases' studies and neither of today's.
        const auto studyDates = [&] {
            QStringList dates;
            for (int i = 0; i < tree->topLevelItemCount(); ++i)
                for (int j = 0; j < tree->topLevelItem(i)->childCount(); ++j) dates << tree->topLevelItem(i)->child(j)->text(1);
            return dates;
        };
        from->clear();
        QTest::keyClicks(from, "20231101");
        QTest::keyClicks(to, "20231130");
        QTest::keyClick(to, Qt::Key_Return);
        QCOMPARE(tree->topLevelItemCount(), 1);
        QVERIFY2(patients().first().contains("PACS MOVED"), qPrintable(patients().join(", ")));
        QCOMPARE(studyDates(), QStringList{"20231115"});
        from->clear();
        to->clear();
        QTest::keyClicks(from, "20240301");
        QTest::keyClicks(to, "20240301");
        QTest::keyClick(to, Qt::Key_Return);
        QVERIFY2(tree->topLevelItemCount() >= 1 && tree->topLevelItemCount() < all, qPrintable(patients().join(", ")));
        for (const auto& d : studyDates()) QCOMPARE(d, QString("20240301"));
        for (const auto& p : patients()) QVERIFY2(!p.contains("PACS"), qPrintable(p));
        from->clear();
        to->clear();
        QTest::keyClick(text, Qt::Key_Return);
        QCOMPARE(tree->topLevelItemCount(), all);
    }

    // A series without PixelSpacing and ImageOrientationPatient (pydicom): the browser row says
    // so, the views say it in amber, and no orientation letter is drawn as if it were known.
    void seriesWithoutGeometrySaysSoInItsRowAndViews() {
        QSignalSpy imported(window_->browser(), &ui::StudyBrowser::imported);
        window_->browser()->importPaths({QString::fromStdString(dir_.file("cases/nogeometry"))});
        QTRY_COMPARE_WITH_TIMEOUT(imported.count(), 1, 60000);
        auto* tree = window_->browser()->tree();
        QTreeWidgetItem* row = nullptr;
        for (QTreeWidgetItemIterator it(tree); *it; ++it)
            if ((*it)->text(4).contains("spacing unknown, assumed 1 mm")) row = *it;
        QVERIFY2(row, "the series row names the assumed spacing");
        QVERIFY(row->toolTip(0).contains("orientation unknown"));
        emit tree->itemActivated(row, 0);  // as a double-click or Enter on the row does
        const QString label = row->data(0, Qt::UserRole + 3).toString();  // the browser's LabelRole
        QVERIFY(!label.isEmpty());
        QVERIFY(window_->jobs()->waitIdle(120000));
        QTRY_COMPARE_WITH_TIMEOUT(window_->openLabel(), label, 10000);
        QCOMPARE(view()->orientationLabels(), (QStringList{"?", "?", "?", "?"}));
        // The amber note at the top right of the slice view.
        auto* axial = window_->slice(0);
        const QImage shot = axial->grab().toImage();
        int amber = 0;
        for (int y = 0; y < 60 && y < shot.height(); ++y)
            for (int x = shot.width() / 2; x < shot.width(); ++x) {
                const QColor c = shot.pixelColor(x, y);
                amber += c.red() > 200 && c.green() > 120 && c.green() < 200 && c.blue() < 90;
            }
        QVERIFY2(amber > 20, qPrintable(QString("amber pixels of the note: %1").arg(amber)));
        saveArtifact("series-without-geometry.png");
    }

    // A 4D NIfTI (three volumes, written by nibabel) opens volume by volume: File > Open's path,
    // asked for volume 2, builds that volume's octree in the background and shows it.
    void fourDimensionalNiftiOpensTheVolumeAsked() {
        const std::string nii = dir_.file("fourd.nii.gz");
        const auto r = test::runCommand(
            "/usr/bin/python3 -c \"import nibabel as nib, numpy as np; "
            "d = np.stack([np.fromfunction(lambda i, j, k: 1000 * v + (i + j + k) % 50, (24, 24, 24)) for v in range(3)], "
            "axis=-1).astype(np.int16); a = np.diag([-1.0, -1.0, 1.0, 1.0]); "
            "img = nib.Nifti1Image(d, a); img.set_qform(a, 1); img.set_sform(a, 1); nib.save(img, '" + nii + "')\"");
        QVERIFY2(r.exitCode == 0, r.output.c_str());
        QVERIFY(ui::MainWindow::isVolumeFile(QString::fromStdString(nii)));
        QVERIFY(!window_->openVolumeFile(QString::fromStdString(nii), 4));  // there are three
        QVERIFY2(window_->lastError().contains("holds 3 volumes; there is no volume"), qPrintable(window_->lastError()));
        QVERIFY(window_->openVolumeFile(QString::fromStdString(nii), 2));
        QVERIFY(window_->jobs()->waitIdle(120000));
        QTRY_VERIFY_WITH_TIMEOUT(window_->openLabel() == "fourd.nii.gz \u2014 volume 2 of 3", 10000);
        QVERIFY(window_->jobs()->waitIdle(60000));  // the percentile window of what is open
        // Volume 2 holds 1000..1049 (volume 1: 0..49, volume 3: 2000..2049).
        const double centre = window_->slice(0)->windowCentre();
        QVERIFY2(centre > 1000 && centre < 1050, qPrintable(QString::number(centre)));
        QCOMPARE(view()->orientationLabels(), (QStringList{"R", "L", "S", "I"}));
        QVERIFY2(window_->lastNotice().contains("a 4D file of 3 volumes; this is volume 2"), qPrintable(window_->lastNotice()));
    }

    // A 3D Slicer sequence (a 4-D NRRD whose last axis lists volumes, gzip) opens volume by
    // volume the same way.
    void fourDimensionalNrrdOpensTheVolumeAsked() {
        const std::string nrrd = dir_.file("sequence.seq.nrrd");
        {
            std::ofstream f(nrrd, std::ios::binary);
            f << "NRRD0004\ntype: short\ndimension: 4\nspace: right-anterior-superior\nsizes: 24 24 24 3\n"
                 "space directions: (1,0,0) (0,1,0) (0,0,1) none\nkinds: domain domain domain list\n"
                 "endian: little\nencoding: raw\nspace origin: (0,0,0)\n\n";
            for (int v = 0; v < 3; ++v)
                for (int i = 0; i < 24 * 24 * 24; ++i) {
                    const std::int16_t x = std::int16_t(1000 * v + (i % 24 + i / 24 % 24 + i / 576) % 50);
                    f.write(reinterpret_cast<const char*>(&x), 2);
                }
        }
        QVERIFY(!window_->openVolumeFile(QString::fromStdString(nrrd), 4));  // there are three
        QVERIFY2(window_->lastError().contains("holds 3 volumes; there is no volume"), qPrintable(window_->lastError()));
        QVERIFY(window_->openVolumeFile(QString::fromStdString(nrrd), 3));
        QVERIFY(window_->jobs()->waitIdle(120000));
        QTRY_VERIFY_WITH_TIMEOUT(window_->openLabel() == "sequence.seq.nrrd \u2014 volume 3 of 3", 10000);
        QVERIFY(window_->jobs()->waitIdle(60000));
        const double centre = window_->slice(0)->windowCentre();  // volume 3 holds 2000..2049
        QVERIFY2(centre > 2000 && centre < 2050, qPrintable(QString::number(centre)));
        QCOMPARE(view()->orientationLabels(), (QStringList{"R", "L", "S", "I"}));
        QVERIFY2(window_->lastNotice().contains("a 4D file of 3 volumes; this is volume 3"), qPrintable(window_->lastNotice()));
    }

    // A float NRRD with a NaN voxel (and no space: a warning to keep) is refused as its build
    // reads it: the error names the slice, and nothing is left beside the octree never written.
    void aFloatFileWithNanIsRefusedAndLeavesNothing() {
        const std::string nrrd = dir_.file("nan.nrrd");
        {
            std::ofstream f(nrrd, std::ios::binary);
            f << "NRRD0004\ntype: float\ndimension: 3\nsizes: 8 8 8\nspacings: 1 1 1\nendian: little\nencoding: raw\n\n";
            for (int i = 0; i < 512; ++i) {
                const float x = i == 5 * 64 + 3 ? std::nanf("") : float(i);
                f.write(reinterpret_cast<const char*>(&x), 4);
            }
        }
        QVERIFY(window_->openVolumeFile(QString::fromStdString(nrrd), 1));
        QVERIFY(window_->jobs()->waitIdle(120000));
        QTRY_VERIFY_WITH_TIMEOUT(window_->lastError().contains("slice 5 holds 1 NaN (not-a-number) value"), 10000);
        const QDir octrees(QString::fromStdString(dir_.file("db/octrees/files")));
        for (const QString& name : octrees.entryList(QDir::Files)) {
            const QString octree = name.endsWith(".warnings") ? name.chopped(9) : name;
            QVERIFY2(!name.endsWith(".warnings") || octrees.exists(octree), qPrintable("notes without an octree: " + name));
        }
    }

    // A NRRD without a space (written here by hand) cannot be placed in the patient: the views
    // draw "?" for the orientation letters, and the status bar says why once it is shown.
    void aNrrdWithoutSpaceShowsNoOrientationLetters() {
        const std::string nrrd = dir_.file("nospace.nrrd");
        {
            std::ofstream f(nrrd, std::ios::binary);
            f << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 16 16 16\nspacings: 1 1 1\nencoding: raw\n\n";
            for (int i = 0; i < 16 * 16 * 16; ++i) f.put(char(i % 16 < 8 ? 40 : 200));
        }
        QVERIFY(window_->openVolumeFile(QString::fromStdString(nrrd), 1));
        QVERIFY(window_->jobs()->waitIdle(120000));
        QTRY_VERIFY_WITH_TIMEOUT(window_->openLabel() == "nospace.nrrd", 10000);
        QCOMPARE(view()->orientationLabels(), (QStringList{"?", "?", "?", "?"}));
        QVERIFY2(window_->lastNotice().contains("orientation unknown"), qPrintable(window_->lastNotice()));
        saveArtifact("nrrd-without-space.png");
        // Another file's octree opens without the notice; the first, found built, says it again.
        QVERIFY(window_->openVolumeFile(QString::fromStdString(dir_.file("fourd.nii.gz")), 1));
        QVERIFY(window_->jobs()->waitIdle(120000));
        QTRY_VERIFY_WITH_TIMEOUT(window_->openLabel() == "fourd.nii.gz \u2014 volume 1 of 3", 10000);
        QVERIFY2(!window_->lastNotice().contains("orientation unknown"), qPrintable(window_->lastNotice()));
        QVERIFY(window_->openVolumeFile(QString::fromStdString(nrrd), 1));
        QCOMPARE(window_->openLabel(), QString("nospace.nrrd"));  // at once: no build
        QVERIFY2(window_->lastNotice().contains("orientation unknown"), qPrintable(window_->lastNotice()));
    }

    // A study's context menu removes it from this workstation after asking: the study leaves
    // the browser, the files received into the PACS settings' storage folder and its octree are
    // deleted, and the files of a study imported from the user's own folder stay.
    void removingAStudyDeletesWhatWasReceivedAndKeepsWhatWasImported() {
        auto settings = dicom::PacsSettings::load(dir_.file("pacs.json"));
        settings.local.storageDir = dir_.file("received");
        settings.save(dir_.file("pacs.json"));
        // Received as a retrieve receives: through the IncomingStore, into <storage>/<study>/<series>.
        std::vector<std::string> received;
        dicom::IncomingStore store(dir_.file("received"));
        for (const auto& f : writeSeries(dir_.file("sent"), "GONE^RECEIVED", 21)) {
            const std::string part = store.temporaryPath();
            std::filesystem::copy_file(f, part, std::filesystem::copy_options::overwrite_existing);
            received.push_back(store.finalize(part).path);
        }
        const auto mine = writeSeries(dir_.file("mine"), "GONE^MINE", 22);
        auto* browser = window_->browser();
        browser->importPaths({QString::fromStdString(dir_.file("received")), QString::fromStdString(dir_.file("mine"))});
        QVERIFY(window_->jobs()->waitIdle(120000));
        auto studyOf = [&](const QString& patient) -> QTreeWidgetItem* {
            browser->refresh();
            for (int i = 0; i < browser->tree()->topLevelItemCount(); ++i)
                if (browser->tree()->topLevelItem(i)->text(0) == patient) return browser->tree()->topLevelItem(i)->child(0);
            return nullptr;
        };
        auto removeByMenu = [&](QTreeWidgetItem* study) {
            browser->tree()->scrollToItem(study);
            const QPoint at = browser->tree()->visualItemRect(study).center();
            // The menu, then the question: each answered once it is up.
            QTimer::singleShot(200, [] {
                auto* menu = qobject_cast<QMenu*>(QApplication::activePopupWidget());
                QVERIFY(menu && !menu->actions().isEmpty());
                QVERIFY(menu->actions().first()->text().startsWith("Remove study"));
                QTimer::singleShot(200, [] {
                    auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget());
                    QVERIFY(box && box->objectName() == "removeStudyQuestion");
                    QVERIFY2(box->informativeText().contains("stay where they are"), qPrintable(box->informativeText()));
                    box->grab().save(test::guiArtifacts() + "/remove-study-question.png");
                    box->button(QMessageBox::Yes)->click();
                });
                menu->actions().first()->trigger();
                menu->close();
            });
            emit browser->tree()->customContextMenuRequested(at);
            QVERIFY(window_->jobs()->waitIdle(60000));
        };
        QTreeWidgetItem* study = studyOf("GONE RECEIVED");
        QVERIFY(study);
        removeByMenu(study);
        QVERIFY(!studyOf("GONE RECEIVED"));
        QTRY_VERIFY2(window_->statusBar()->currentMessage().contains("48 received file(s)"),
                     qPrintable(window_->statusBar()->currentMessage()));
        for (const auto& f : received) QVERIFY2(!std::filesystem::exists(f), f.c_str());
        QVERIFY(!std::filesystem::exists(std::filesystem::path(received.front()).parent_path().parent_path()));
        QVERIFY(std::filesystem::is_directory(dir_.file("received")));
        study = studyOf("GONE MINE");
        QVERIFY(study);
        removeByMenu(study);
        QVERIFY(!studyOf("GONE MINE"));
        QTRY_VERIFY2(window_->statusBar()->currentMessage().contains("48 imported file(s) kept"),
                     qPrintable(window_->statusBar()->currentMessage()));
        for (const auto& f : mine) QVERIFY2(std::filesystem::exists(f), f.c_str());
    }

    void cleanupTestCase() { close(); }
};

int main(int argc, char** argv) { return test::runGuiTests<StudyBrowserTest>(argc, argv); }

#include "StudyBrowserTest.moc"
