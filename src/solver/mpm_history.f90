!> The energy history of a run, history.csv: its header and one line per output of the
!> energies (mpm_energy), followed by the reactions of the faces that hold their nodes (sliding, fixed, velocity) and the reactions
!> and displacements of the regions of prescribed_motion. Written through the C library
!> (mpm_filesystem::text_file_type): gfortran does not report a write to a full disk.
module mpm_history
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case, only: case_type
    use mpm_boundary, only: face_nodes_type
    use mpm_filesystem, only: file_exists, text_file_type, open_text_file, put_line
    use mpm_simulation, only: simulation_type
    use mpm_energy, only: energy_total, energy_residual
    use mpm_motion, only: region_count, region_displacement, body_displacement
    implicit none
    private
    public :: open_history, write_history

contains

    !> Open the energy history: a new file with its header, or (restart) the file of the run.
    !> (Written through the C library: gfortran does not report a write to a full disk.)
    subroutine open_history(case, resumed, unit, error)
        type(case_type), intent(in) :: case
        logical, intent(in) :: resumed
        type(text_file_type), intent(inout) :: unit
        type(error_type), allocatable, intent(out) :: error

        if (resumed .and. file_exists(case%output%directory//"/history.csv")) then
            call open_text_file(case%output%directory//"/history.csv", unit, error, append=.true.)
        else
            call open_text_file(case%output%directory//"/history.csv", unit, error)
            if (.not. allocated(error)) call put_line(unit, "time,step,kinetic_energy,"// &
                "elastic_energy,potential_energy,plastic_work,viscous_work,damping_work,"// &
                "friction_work,load_work,boundary_work,transfer_loss,total,residual"// &
                reaction_header(case))
        end if
    end subroutine open_history

    !> One line of the energy history (a failed write is reported by the next flush).
    subroutine write_history(unit, sim)
        type(text_file_type), intent(inout) :: unit
        type(simulation_type), intent(in) :: sim

        character(len=:), allocatable :: line
        character(len=512) :: energies
        character(len=24) :: value
        integer :: side, axis, d, r
        real(wp) :: shift(3), reaction

        associate (e => sim%energy)
            write (energies, "(es23.15e3,',',i0,12(',',es23.15e3))") sim%time, sim%step, &
                e%kinetic, e%elastic, e%potential, e%plastic, e%viscous, e%damping, e%friction, &
                e%loads, e%boundary, e%transfer, energy_total(e), energy_residual(e)
        end associate
        line = trim(energies)
        if (len(reaction_header(sim%case)) == 0) then
            call put_line(unit, trim(line))
            return
        end if
        ! the reaction of each holding face, after the energies
        do axis = 1, sim%case%dim
            do side = 1, 2
                if (.not. has_reaction(sim%case, side, axis)) cycle
                do d = 1, sim%case%dim
                    write (value, "(',',es23.15e3)") sim%face_reaction(d, side, axis)
                    line = trim(line)//value
                end do
            end do
        end do
        ! the reaction and displacement of each region of prescribed_motion
        do r = 1, region_count(sim%case)
            if (sim%case%motions(r)%rigid > 0) then
                shift = body_displacement(sim%case, sim%particles, r)
            else
                shift = region_displacement(sim%case, r, sim%time)
            end if
            do d = 1, sim%case%dim
                reaction = 0.0_wp
                if (allocated(sim%region_reaction)) reaction = sim%region_reaction(d, r)
                write (value, "(',',es23.15e3)") reaction
                line = trim(line)//value
            end do
            do d = 1, sim%case%dim
                write (value, "(',',es23.15e3)") shift(d)
                line = trim(line)//value
            end do
        end do
        call put_line(unit, trim(line))
    end subroutine write_history

    !> The columns of the reactions of the holding faces in history.csv,
    !> ",reaction_ymax_x,reaction_ymax_y", then the reaction and displacement of each region
    !> of prescribed_motion, ",reaction_footing_x,...,displacement_footing_y" (empty without
    !> either).
    function reaction_header(case) result(text)
        type(case_type), intent(in) :: case
            !! resolved case
        character(len=:), allocatable :: text

        character(len=*), parameter :: axes = "xyz"
        integer :: side, axis, d, r

        text = ""
        do axis = 1, case%dim
            do side = 1, 2
                if (.not. has_reaction(case, side, axis)) cycle
                do d = 1, case%dim
                    text = text//",reaction_"//axes(axis:axis)//trim(merge("min", "max", &
                        side == 1))//"_"//axes(d:d)
                end do
            end do
        end do
        do r = 1, region_count(case)
            do d = 1, case%dim
                text = text//",reaction_"//case%motions(r)%name//"_"//axes(d:d)
            end do
            do d = 1, case%dim
                text = text//",displacement_"//case%motions(r)%name//"_"//axes(d:d)
            end do
        end do
    end function reaction_header

    !> Whether a face holds velocity components of its nodes (sliding, fixed, velocity): its
    !> reaction is a history column.
    logical function has_reaction(case, side, axis)
        type(case_type), intent(in) :: case
            !! resolved case
        integer, intent(in) :: side, axis
            !! the face: 1 min, 2 max; its axis

        type(face_nodes_type) :: nodes

        nodes = case%domain%nodes(side, axis, case%dim)
        has_reaction = any(nodes%held(1:case%dim))
    end function has_reaction

end module mpm_history
