using System.Globalization;
using System.Net;
using System.Text;
using PmacStream.Hmi;

namespace PmacStream.Core.Tests.Hmi;

/// <summary>
/// Draws the WinForms screen without Windows: the same <see cref="HmiLayout"/> boxes the form places its controls
/// in, the same kinds of control, and the texts the presenter put into the view, as an HTML page of absolutely
/// placed boxes (headless chromium turns it into docs/hmi-screen.png). What MainForm.cs places, in the same order.
/// </summary>
internal static class ScreenSketch
{
    internal enum Kind { Group, Label, Combo, Text, Numeric, Button, Check, List, VirtualList, TrackBar, Progress, Log }

    internal sealed record Control(string Name, Kind Kind, LayoutBox Box, string? Parent, Func<FakeView, string> Text, Func<FakeView, bool>? Enabled = null);

    /// <summary>The form's controls: name, kind, box, parent group (null: the form) and what they show.</summary>
    internal static IReadOnlyList<Control> Controls { get; } = Build();

    private static List<Control> Build()
    {
        static Func<FakeView, string> T(TextId id) => v => v.Texts[id];
        var list = new List<Control>
        {
            new("grpConnection", Kind.Group, HmiLayout.ConnectionGroup, null, T(TextId.ConnectionGroup)),
            new("lblDevice", Kind.Label, HmiLayout.DeviceLabel, "grpConnection", T(TextId.DeviceType)),
            new("cboDevice", Kind.Combo, HmiLayout.DeviceCombo, "grpConnection", v => v.Texts[TextId.DeviceSimulator], v => v.Commands.Connect),
            new("lblIp", Kind.Label, HmiLayout.IpLabel, "grpConnection", T(TextId.IpAddress)),
            new("txtIp", Kind.Text, HmiLayout.IpText, "grpConnection", v => v.ConnectionSettings.EthernetAddress, v => v.Commands.Connect),
            new("lblPort", Kind.Label, HmiLayout.PortLabel, "grpConnection", T(TextId.SerialPort)),
            new("cboPort", Kind.Combo, HmiLayout.PortCombo, "grpConnection", v => v.ConnectionSettings.SerialPort, v => v.Commands.Connect),
            new("lblBaud", Kind.Label, HmiLayout.BaudLabel, "grpConnection", T(TextId.Baud)),
            new("cboBaud", Kind.Combo, HmiLayout.BaudCombo, "grpConnection", v => v.ConnectionSettings.Baud.ToString(CultureInfo.InvariantCulture), v => v.Commands.Connect),
            new("lblDeviceNumber", Kind.Label, HmiLayout.DeviceNumberLabel, "grpConnection", T(TextId.DeviceNumber)),
            new("numDeviceNumber", Kind.Numeric, HmiLayout.DeviceNumberBox, "grpConnection", v => v.ConnectionSettings.PcommDevice.ToString(CultureInfo.InvariantCulture), v => v.Commands.Connect),
            new("btnConnect", Kind.Button, HmiLayout.ConnectButton, "grpConnection", T(TextId.Connect), v => v.Commands.Connect),
            new("btnDisconnect", Kind.Button, HmiLayout.DisconnectButton, "grpConnection", T(TextId.Disconnect), v => v.Commands.Disconnect),
            new("lblConnectionState", Kind.Label, HmiLayout.ConnectionStateLabel, "grpConnection", v => v.ConnectionState),

            new("grpProgram", Kind.Group, HmiLayout.ProgramGroup, null, T(TextId.ProgramGroup)),
            new("btnOpen", Kind.Button, HmiLayout.OpenButton, "grpProgram", T(TextId.Open), v => v.Commands.Open),
            new("lblPath", Kind.Label, HmiLayout.PathLabel, "grpProgram", v => Path.GetFileName(v.ProgramPath)),
            new("btnCheck", Kind.Button, HmiLayout.CheckButton, "grpProgram", T(TextId.Check), v => v.Commands.Check),
            new("btnSplit", Kind.Button, HmiLayout.SplitButton, "grpProgram", T(TextId.Split), v => v.Commands.Split),
            new("lblLinesPerChunk", Kind.Label, HmiLayout.LinesPerChunkLabel, "grpProgram", T(TextId.LinesPerChunk)),
            new("numLinesPerChunk", Kind.Numeric, HmiLayout.LinesPerChunkBox, "grpProgram", v => v.LinesPerChunk.ToString(CultureInfo.InvariantCulture), v => v.Commands.Split),
            new("lblStrategy", Kind.Label, HmiLayout.StrategyLabel, "grpProgram", T(TextId.Strategy)),
            new("cboStrategy", Kind.Combo, HmiLayout.StrategyCombo, "grpProgram", v => v.SelectedStrategy, v => v.Commands.Execute),
            new("lblLanguage", Kind.Label, HmiLayout.LanguageLabel, "grpProgram", T(TextId.Language)),
            new("cboLanguage", Kind.Combo, HmiLayout.LanguageCombo, "grpProgram", v => v.Language == HmiLanguage.Chinese ? "简体中文" : "English"),

            new("grpFeed", Kind.Group, HmiLayout.FeedGroup, null, T(TextId.Feed)),
            new("lblFeed", Kind.Label, HmiLayout.FeedLabel, "grpFeed", T(TextId.Feed)),
            new("trkFeed", Kind.TrackBar, HmiLayout.FeedTrackBar, "grpFeed", v => ((v.Feed - v.FeedScale.Minimum) / (v.FeedScale.Maximum - v.FeedScale.Minimum)).ToString(CultureInfo.InvariantCulture)),
            new("numFeed", Kind.Numeric, HmiLayout.FeedBox, "grpFeed", v => v.Feed.ToString("0", CultureInfo.InvariantCulture)),
            new("lblFeedUnit", Kind.Label, HmiLayout.FeedUnitLabel, "grpFeed", v => v.FeedScale.Unit),
            new("chkSingleBlock", Kind.Check, HmiLayout.SingleBlockCheck, "grpFeed", T(TextId.SingleBlock)),

            new("lblChunkFiles", Kind.Label, HmiLayout.ChunkFilesLabel, null, T(TextId.ChunkFiles)),
            new("listBox1", Kind.List, HmiLayout.ChunkFilesList, null, v => string.Join("\n", v.ChunkFiles)),
            new("lblChunkLines", Kind.Label, HmiLayout.ChunkLinesLabel, null, T(TextId.ChunkLines)),
            new("lvChunkLines", Kind.VirtualList, HmiLayout.ChunkLinesList, null, v => "chunk"),
            new("lblProgramLines", Kind.Label, HmiLayout.ProgramLinesLabel, null, T(TextId.ProgramLines)),
            new("listBox2", Kind.VirtualList, HmiLayout.ProgramLinesList, null, v => "program"),

            new("btnExecute", Kind.Button, HmiLayout.ExecuteButton, null, T(TextId.Execute), v => v.Commands.Execute),
            new("btnHold", Kind.Button, HmiLayout.HoldButton, null, T(TextId.Hold), v => v.Commands.Hold),
            new("btnResume", Kind.Button, HmiLayout.ResumeButton, null, T(TextId.Resume), v => v.Commands.Resume),
            new("btnAbort", Kind.Button, HmiLayout.AbortButton, null, T(TextId.Abort), v => v.Commands.Abort),
            new("btnStartFromLine", Kind.Button, HmiLayout.StartFromLineButton, null, T(TextId.StartFromLine), v => v.Commands.StartFromLine),
            new("btnResumeInterrupted", Kind.Button, HmiLayout.ResumeInterruptedButton, null, T(TextId.ResumeInterrupted), v => v.Commands.ResumeInterrupted),
            new("grpStatus", Kind.Group, HmiLayout.StatusGroup, null, T(TextId.JobState)),
        };

        for (var row = 0; row < HmiLayout.StatusRows.Count; row++)
        {
            var r = row;
            list.Add(new($"lblStatusCaption{r}", Kind.Label, HmiLayout.StatusCaption(r), "grpStatus", v => v.Texts[HmiLayout.StatusRows[r]]));
            list.Add(new($"lblStatusValue{r}", Kind.Label, HmiLayout.StatusValue(r), "grpStatus", v => StatusValue(v.Status, r)));
        }

        list.Add(new("progressBar", Kind.Progress, HmiLayout.ProgressBar, "grpStatus", v => v.Status.ProgressPercent.ToString(CultureInfo.InvariantCulture)));
        list.Add(new("lblDiagnostics", Kind.Label, HmiLayout.DiagnosticsLabel, null, T(TextId.Diagnostics)));
        list.Add(new("lstDiagnostics", Kind.List, HmiLayout.DiagnosticsList, null, v => string.Join("\n", v.Diagnostics)));
        list.Add(new("lblLog", Kind.Label, HmiLayout.LogLabel, null, T(TextId.Log)));
        list.Add(new("txtLog", Kind.Log, HmiLayout.LogText, null, v => string.Join("\n", v.Log.TakeLast(9))));
        return list;
    }

    internal static string StatusValue(StatusDisplay s, int row) =>
        new[] { s.State, s.TotalFiles, s.ProgramLines, s.CurrentFile, s.CurrentLine, s.Progress, s.Feed, s.Elapsed, s.Eta }[row];

    /// <summary>The page: a window frame, the controls, the status strip.</summary>
    internal static string Render(FakeView v, string title, int programTopLine, int chunkTopLine, int selectedChunk)
    {
        var sb = new StringBuilder();
        var w = HmiLayout.ClientWidth;
        var h = HmiLayout.ClientHeight + HmiLayout.StatusStripHeight;
        sb.Append(CultureInfo.InvariantCulture, $$"""
            <!DOCTYPE html><html><head><meta charset="utf-8"><style>
            body{margin:0;background:#6b7b8c;font:12px "Segoe UI","DejaVu Sans","Noto Sans CJK SC",sans-serif;}
            .win{position:absolute;left:10px;top:10px;width:{{w + 2}}px;height:{{h + 32}}px;background:#f0f0f0;border:1px solid #1883d7;box-shadow:0 6px 24px rgba(0,0,0,.45)}
            .title{height:30px;line-height:30px;padding-left:10px;background:#fff;color:#000;font-size:12px}
            .title span.btns{float:right;letter-spacing:28px;padding-right:4px;color:#333}
            .client{position:absolute;left:1px;top:31px;width:{{w}}px;height:{{h}}px}
            .c{position:absolute;box-sizing:border-box;overflow:hidden;white-space:nowrap}
            .grp{border:1px solid #d5dfe5;border-radius:3px}
            .grp>.legend{position:absolute;left:7px;top:-9px;background:#f0f0f0;padding:0 2px;color:#0046d5}
            .lbl{line-height:18px;color:#000}
            .box{background:#fff;border:1px solid #7a7a7a;padding:2px 4px;line-height:17px}
            .combo:after{content:"\2304";position:absolute;right:5px;top:-2px;color:#333}
            .num:after{content:"\25B4\A\25BE";white-space:pre;position:absolute;right:3px;top:-1px;font-size:8px;line-height:9px;color:#333}
            .btn{background:#e1e1e1;border:1px solid #adadad;text-align:center;display:flex;align-items:center;justify-content:center}
            .btn.exec{font-weight:bold;font-size:14px;background:#dff0d8;border-color:#5cb85c}
            .off{color:#a0a0a0!important;border-color:#ccc!important;background:#ececec!important}
            .list{background:#fff;border:1px solid #828790;font:12px "Segoe UI","DejaVu Sans","Noto Sans CJK SC",sans-serif;white-space:pre}
            .list div{height:16px;line-height:16px;padding-left:3px}
            .list .sel{background:#0078d7;color:#fff}
            .lv{background:#fff;border:1px solid #828790;font:12px "DejaVu Sans Mono","Noto Sans CJK SC",monospace}
            .lv .hdr{height:22px;line-height:22px;border-bottom:1px solid #e5e5e5;font:12px "Segoe UI","DejaVu Sans","Noto Sans CJK SC",sans-serif;color:#4c607a}
            .lv .row{height:17px;line-height:17px;white-space:pre}
            .lv .n{display:inline-block;width:{{HmiLayout.LineNumberColumnWidth - 10}}px;text-align:right;padding-right:10px;color:#666}
            .lv .exe{background:gold;font-weight:bold}
            .lv .exe .n{color:#000}
            .lv .sel{background:#cce8ff}
            .sb{position:absolute;right:0;top:23px;bottom:0;width:16px;background:#f0f0f0;border-left:1px solid #e5e5e5}
            .sb i{position:absolute;left:3px;width:9px;height:30px;background:#c2c2c2;border-radius:1px}
            .trk:before{content:"";position:absolute;left:8px;right:8px;top:10px;height:3px;background:#e7eaea;border:1px solid #d6d6d6}
            .trk i{position:absolute;top:3px;width:10px;height:18px;background:#007ad9;border-radius:2px}
            .trk b{position:absolute;top:27px;width:1px;height:4px;background:#999}
            .chk:before{content:"";display:inline-block;width:11px;height:11px;border:1px solid #333;background:#fff;margin-right:5px;vertical-align:-2px}
            .prg{background:#e6e6e6;border:1px solid #bcbcbc}
            .prg i{display:block;height:100%;background:#06b025}
            .log{background:#fff;border:1px solid #7a7a7a;font:11px "DejaVu Sans Mono","Noto Sans CJK SC",monospace;white-space:pre;padding:2px 4px;line-height:14px}
            .val{font-weight:bold}
            .strip{position:absolute;left:0;bottom:0;width:100%;height:{{HmiLayout.StatusStripHeight}}px;line-height:{{HmiLayout.StatusStripHeight}}px;background:#f0f0f0;border-top:1px solid #d7d7d7;padding-left:8px;box-sizing:border-box}
            .strip span{float:right;padding-right:20px}
            </style></head><body><div class="win"><div class="title">{{E(title)}}<span class="btns">&#x2013; &#x2610; &#x2715;</span></div><div class="client">
            """);

        var byName = Controls.ToDictionary(c => c.Name);
        foreach (var c in Controls)
        {
            var (x, y) = (c.Box.X, c.Box.Y);
            if (c.Parent is { } p)
            {
                x += byName[p].Box.X;
                y += byName[p].Box.Y;
            }

            var enabled = c.Enabled?.Invoke(v) ?? true;
            var off = enabled ? string.Empty : " off";
            var style = string.Create(CultureInfo.InvariantCulture, $"left:{x}px;top:{y}px;width:{c.Box.Width}px;height:{c.Box.Height}px");
            var text = c.Text(v);
            switch (c.Kind)
            {
                case Kind.Group:
                    sb.Append($"<div class=\"c grp\" style=\"{style};overflow:visible\"><span class=\"legend\">{E(text)}</span></div>");
                    break;
                case Kind.Label:
                    var bold = c.Name.StartsWith("lblStatusValue", StringComparison.Ordinal) ? " val" : string.Empty;
                    sb.Append($"<div class=\"c lbl{bold}\" style=\"{style};white-space:pre-wrap\">{E(text)}</div>");
                    break;
                case Kind.Combo:
                    sb.Append($"<div class=\"c box combo{off}\" style=\"{style}\">{E(text)}</div>");
                    break;
                case Kind.Text:
                    sb.Append($"<div class=\"c box{off}\" style=\"{style}\">{E(text)}</div>");
                    break;
                case Kind.Numeric:
                    sb.Append($"<div class=\"c box num{off}\" style=\"{style}\">{E(text)}</div>");
                    break;
                case Kind.Button:
                    var exec = c.Name == "btnExecute" ? " exec" : string.Empty;
                    sb.Append($"<div class=\"c btn{exec}{off}\" style=\"{style}\">{E(text)}</div>");
                    break;
                case Kind.Check:
                    sb.Append($"<div class=\"c lbl chk\" style=\"{style}\">{E(text)}</div>");
                    break;
                case Kind.TrackBar:
                    var f = double.Parse(text, CultureInfo.InvariantCulture);
                    sb.Append($"<div class=\"c trk\" style=\"{style}\">");
                    for (var t = 0; t <= 20; t++)
                    {
                        sb.Append(CultureInfo.InvariantCulture, $"<b style=\"left:{12 + (t * (c.Box.Width - 24) / 20)}px\"></b>");
                    }

                    sb.Append(CultureInfo.InvariantCulture, $"<i style=\"left:{7 + (int)(f * (c.Box.Width - 24))}px\"></i></div>");
                    break;
                case Kind.Progress:
                    sb.Append($"<div class=\"c prg\" style=\"{style}\"><i style=\"width:{text}%\"></i></div>");
                    break;
                case Kind.Log:
                    sb.Append($"<div class=\"c log\" style=\"{style}\">{E(text)}</div>");
                    break;
                case Kind.List:
                    sb.Append($"<div class=\"c list\" style=\"{style}\">");
                    var rows = text.Length == 0 ? [] : text.Split('\n');
                    for (var i = 0; i < rows.Length && i * 16 < c.Box.Height; i++)
                    {
                        var sel = c.Name == "listBox1" && i == selectedChunk ? " class=\"sel\"" : string.Empty;
                        sb.Append($"<div{sel}>{E(rows[i])}</div>");
                    }

                    sb.Append("</div>");
                    break;
                case Kind.VirtualList:
                    var program = text == "program";
                    var count = program ? v.ProgramLineCount : v.ChunkLineCount;
                    var top = program ? programTopLine : chunkTopLine;
                    var visible = (c.Box.Height - 24) / 17;
                    sb.Append($"<div class=\"c lv\" style=\"{style}\"><div class=\"hdr\"><span class=\"n\">{E(v.Texts[TextId.LineColumn])}</span>{E(v.Texts[TextId.TextColumn])}</div>");
                    for (var line = top; line < top + visible && line <= count; line++)
                    {
                        var row = program ? v.ProgramRow(line) : v.ChunkRow(line);
                        var cls = program && line == v.ExecutingLine ? "row exe" : program && line == v.SelectedLine ? "row sel" : "row";
                        sb.Append(CultureInfo.InvariantCulture, $"<div class=\"{cls}\"><span class=\"n\">{line}</span>{E(row)}</div>");
                    }

                    var thumb = count <= visible ? 0 : (int)((double)(top - 1) / Math.Max(1, count - visible) * (c.Box.Height - 24 - 30));
                    sb.Append(CultureInfo.InvariantCulture, $"<div class=\"sb\"><i style=\"top:{thumb}px\"></i></div></div>");
                    break;
            }
        }

        sb.Append($"<div class=\"strip\">{E(v.Status.State + "   " + v.Status.CurrentLine + "   " + v.Status.Progress)}<span>{E(v.ConnectionState)}</span></div>");
        sb.Append("</div></div></body></html>");
        return sb.ToString();
    }

    private static string E(string s) => WebUtility.HtmlEncode(s);
}
