using System.Text.RegularExpressions;
using PmacStream.Hmi;

namespace PmacStream.Core.Tests.Hmi;

/// <summary>
/// The layout table as the form uses it, checked without a screen: every <c>Place(control, HmiLayout.Box, parent)</c>
/// call in MainForm.cs, plus the status rows it places in a loop. The form itself is tested on a real screen by
/// tests/PmacStream.WinForms.UiTests.
/// </summary>
public sealed class ScreenLayoutTests
{
    private sealed record Placed(string Name, LayoutBox Box, string Parent);

    private static bool Overlap(LayoutBox a, LayoutBox b) =>
        a.X < b.X + b.Width && b.X < a.X + a.Width && a.Y < b.Y + b.Height && b.Y < a.Y + a.Height;

    [Fact]
    public void No_two_controls_of_one_container_overlap_and_all_fit()
    {
        var source = File.ReadAllText(Path.Combine(RepoRoot.Path, "src", "PmacStream.WinForms", "MainForm.cs"));
        var placed = Regex.Matches(source, @"Place\((\w+), HmiLayout\.(\w+), (\w+)\)")
            .Select(m => new Placed(m.Groups[1].Value, (LayoutBox)typeof(HmiLayout).GetField(m.Groups[2].Value)!.GetValue(null)!, m.Groups[3].Value))
            .ToList();
        placed.Should().HaveCountGreaterThan(40, "the form places its controls from the layout table");
        source.Should().Contain("Place(lblStatusCaptions[row], HmiLayout.StatusCaption(row), grpStatus)");
        source.Should().Contain("Place(lblStatusValues[row], HmiLayout.StatusValue(row), grpStatus)");
        for (var row = 0; row < HmiLayout.StatusRows.Count; row++)
        {
            placed.Add(new Placed($"status caption {row}", HmiLayout.StatusCaption(row), "grpStatus"));
            placed.Add(new Placed($"status value {row}", HmiLayout.StatusValue(row), "grpStatus"));
        }

        // The profile selector, the optional-stop box and the program-stop banner are on the form, where they were kept free.
        placed.Should().Contain(c => c.Name == "cboProfile" && c.Box == HmiLayout.ProfileCombo && c.Parent == "grpProgram");
        placed.Should().Contain(c => c.Name == "lblProfile" && c.Box == HmiLayout.ProfileLabel && c.Parent == "grpProgram");
        placed.Should().Contain(c => c.Name == "chkOptionalStop" && c.Box == HmiLayout.OptionalStopCheck && c.Parent == "grpFeed");
        placed.Should().Contain(c => c.Name == "lblProgramStop" && c.Box == HmiLayout.ProgramStopBanner && c.Parent == "this");
        placed.Should().Contain(c => c.Box == HmiLayout.ToolpathPane, "the toolpath pane is on the form");

        foreach (var group in placed.GroupBy(c => c.Parent))
        {
            var items = group.ToList();
            for (var i = 0; i < items.Count; i++)
            {
                for (var j = i + 1; j < items.Count; j++)
                {
                    Overlap(items[i].Box, items[j].Box).Should().BeFalse($"{items[i].Name} and {items[j].Name} overlap");
                }

                var box = items[i].Box;
                if (group.Key == "this")
                {
                    (box.X + box.Width).Should().BeLessThanOrEqualTo(HmiLayout.ClientWidth, items[i].Name);
                    (box.Y + box.Height).Should().BeLessThanOrEqualTo(HmiLayout.ClientHeight, items[i].Name);
                }
                else
                {
                    var parent = placed.Single(c => c.Name == group.Key).Box;
                    (box.X + box.Width).Should().BeLessThanOrEqualTo(parent.Width, $"{items[i].Name} fits in {group.Key}");
                    (box.Y + box.Height).Should().BeLessThanOrEqualTo(parent.Height, $"{items[i].Name} fits in {group.Key}");
                }
            }
        }
    }
}
